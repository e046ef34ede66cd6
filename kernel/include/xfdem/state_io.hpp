// State hashing and snapshots, for every kind of state the kernel steps:
// DemState<1|2|3>, BarState, PlateState, CoupledState and Coupled2dState.
//
//   state_hash(state)                 64-bit FNV-1a over the raw bits of every field, in visitor order
//   field_hashes(state, out)          one FNV-1a per field (a replay names the first field that differs)
//   save_snapshot(state, buffer)      header + the same raw bits, into a caller buffer
//   restore_snapshot(state, buffer)   validated copy back; a refused snapshot leaves the state untouched
//
// The fields are the ones the states' own visitors list (DemState::for_each_array,
// BarState::for_each_field, PlateState::for_each_field, Coupled2dState::for_each_field,
// and for_each_field(CoupledState&) below), so a field
// added to a visitor is hashed, saved, restored and named without further code.
// Hash, save and restore never allocate and never throw; the file helpers at the
// end are for tools and do allocate. docs/determinism.md gives the format, the
// refusal rules and the determinism contract.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

#include "xfdem/bar.hpp"
#include "xfdem/plate.hpp"
#include "xfdem/coupled.hpp"
#include "xfdem/coupled2d.hpp"
#include "xfdem/dem.hpp"

namespace xfdem {

// ---- the hash ----------------------------------------------------------------

/// FNV-1a, 64 bit (offset basis 0xcbf29ce484222325, prime 0x100000001b3), one
/// byte at a time. Fixed forever: golden hashes in tests depend on it.
inline constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
inline constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;
constexpr std::uint64_t fnv1a(const std::byte* data, std::size_t bytes, std::uint64_t hash = kFnvOffset) noexcept {
  for (std::size_t k = 0; k < bytes; ++k) {
    hash ^= static_cast<std::uint64_t>(data[k]);
    hash *= kFnvPrime;
  }
  return hash;
}

// ---- a uniform visitor over every state --------------------------------------

/// Calls visit(part, name, data, count) for every field of the state, in a fixed
/// order: `part` is "" for a DemState, BarState or PlateState on its own,
/// "dem", "bar" or "" (its own scalars) inside a CoupledState, and "dem",
/// "plate", "springs" or "" inside a Coupled2dState; `data` points at `count`
/// elements of double, std::int64_t or std::int32_t. A name repeats when an
/// array has one column per axis or slot ("x" D times, "hist_v" 4·D times).
template <int D, class Visitor>
void for_each_field(DemState<D>& state, Visitor&& visit) {
  state.for_each_array(
      [&](const char* name, auto* data, auto count) { visit("", name, data, static_cast<std::size_t>(count)); });
}
template <class Visitor>
void for_each_field(BarState& state, Visitor&& visit) {
  state.for_each_field([&](const char* name, auto* data, std::size_t count) { visit("", name, data, count); });
}
template <class Visitor>
void for_each_field(PlateState& state, Visitor&& visit) {
  state.for_each_field([&](const char* name, auto* data, std::size_t count) { visit("", name, data, count); });
}
/// The particles ("dem"), then the bar ("bar"), then the coupling's own scalars.
template <class Visitor>
void for_each_field(CoupledState& state, Visitor&& visit) {
  state.dem.for_each_array(
      [&](const char* name, auto* data, auto count) { visit("dem", name, data, static_cast<std::size_t>(count)); });
  state.bar.for_each_field([&](const char* name, auto* data, std::size_t count) { visit("bar", name, data, count); });
  visit("", "coupling_force", &state.coupling_force, std::size_t{1});
  visit("", "pending_impulse", &state.pending_impulse, std::size_t{1});
  visit("", "impulse_to_particles", &state.impulse_to_particles, std::size_t{1});
  visit("", "impulse_to_bar", &state.impulse_to_bar, std::size_t{1});
  visit("", "coupling_slope", &state.coupling_slope, std::size_t{1});
  visit("", "coupling_slope_width", &state.coupling_slope_width, std::size_t{1});
  visit("", "sensitivity", state.sensitivity.data(), state.sensitivity.size());
  visit("", "sensitivity_width", &state.sensitivity_width, std::size_t{1});
  visit("", "sensitivity_signature", &state.sensitivity_signature, std::size_t{1});
  visit("", "last_passes", &state.last_passes, std::size_t{1});
  visit("", "peak_passes", &state.peak_passes, std::size_t{1});
  visit("", "energy_reference", &state.energy.reference, std::size_t{1});
  visit("", "energy_work", &state.energy.work, std::size_t{1});
  visit("", "energy_peak", &state.energy.peak, std::size_t{1});
  visit("", "energy_exceeded", &state.energy.exceeded, std::size_t{1});
  visit("", "step", &state.step, std::size_t{1});
  visit("", "time", &state.time, std::size_t{1});
}

/// The disks ("dem"), the plate ("plate"), the springs ("springs"), then the
/// exchange's own fields: the state's own list (Coupled2dState::for_each_field).
template <class Visitor>
void for_each_field(Coupled2dState& state, Visitor&& visit) {
  state.for_each_field(visit);
}

// ---- hashes --------------------------------------------------------------------
// The full-state hash is FNV-1a over the concatenated raw bytes of every field in
// visitor order (exactly a snapshot's payload, so it is also the payload checksum).
// A field hash is FNV-1a over that field's bytes alone. The layout hash is
// FNV-1a over, for each field: part, '.', name, a NUL byte, the element count and
// the element size (both as 8-byte little-endian integers); two states have the
// same layout hash when they have the same fields with the same sizes.

std::uint64_t state_hash(const DemState<1>& state) noexcept;
std::uint64_t state_hash(const DemState<2>& state) noexcept;
std::uint64_t state_hash(const DemState<3>& state) noexcept;
std::uint64_t state_hash(const BarState& state) noexcept;
std::uint64_t state_hash(const PlateState& state) noexcept;
std::uint64_t state_hash(const CoupledState& state) noexcept;
std::uint64_t state_hash(const Coupled2dState& state) noexcept;

std::uint64_t layout_hash(const DemState<1>& state) noexcept;
std::uint64_t layout_hash(const DemState<2>& state) noexcept;
std::uint64_t layout_hash(const DemState<3>& state) noexcept;
std::uint64_t layout_hash(const BarState& state) noexcept;
std::uint64_t layout_hash(const PlateState& state) noexcept;
std::uint64_t layout_hash(const CoupledState& state) noexcept;
std::uint64_t layout_hash(const Coupled2dState& state) noexcept;

/// Number of fields the visitor lists.
std::size_t field_count(const DemState<1>& state) noexcept;
std::size_t field_count(const DemState<2>& state) noexcept;
std::size_t field_count(const DemState<3>& state) noexcept;
std::size_t field_count(const BarState& state) noexcept;
std::size_t field_count(const PlateState& state) noexcept;
std::size_t field_count(const CoupledState& state) noexcept;
std::size_t field_count(const Coupled2dState& state) noexcept;

/// Writes the hash of field k to out[k] for k < min(out.size(), field_count);
/// returns field_count.
std::size_t field_hashes(const DemState<1>& state, std::span<std::uint64_t> out) noexcept;
std::size_t field_hashes(const DemState<2>& state, std::span<std::uint64_t> out) noexcept;
std::size_t field_hashes(const DemState<3>& state, std::span<std::uint64_t> out) noexcept;
std::size_t field_hashes(const BarState& state, std::span<std::uint64_t> out) noexcept;
std::size_t field_hashes(const PlateState& state, std::span<std::uint64_t> out) noexcept;
std::size_t field_hashes(const CoupledState& state, std::span<std::uint64_t> out) noexcept;
std::size_t field_hashes(const Coupled2dState& state, std::span<std::uint64_t> out) noexcept;

/// Writes the readable name of field k into `buffer` (always NUL-terminated):
/// "part.name", with "[i]" added when the name occurs more than once (the axis,
/// or slot·D + axis for the history rings): "x[1]", "dem.hist_a[3]", "bar.u",
/// "coupling_force". Returns buffer; "?" when k is out of range.
const char* field_name(const DemState<1>& state, std::size_t k, char* buffer, int buffer_size) noexcept;
const char* field_name(const DemState<2>& state, std::size_t k, char* buffer, int buffer_size) noexcept;
const char* field_name(const DemState<3>& state, std::size_t k, char* buffer, int buffer_size) noexcept;
const char* field_name(const BarState& state, std::size_t k, char* buffer, int buffer_size) noexcept;
const char* field_name(const PlateState& state, std::size_t k, char* buffer, int buffer_size) noexcept;
const char* field_name(const CoupledState& state, std::size_t k, char* buffer, int buffer_size) noexcept;
const char* field_name(const Coupled2dState& state, std::size_t k, char* buffer, int buffer_size) noexcept;

/// A hash of what a model is (properties, features, dt, capacities): pass it as
/// the snapshot's model tag so that a snapshot of another scene with the same
/// array sizes is refused too. It covers the model's descriptive fields, not its
/// derived operators.
std::uint64_t model_fingerprint(const DemModel<1>& model) noexcept;
std::uint64_t model_fingerprint(const DemModel<2>& model) noexcept;
std::uint64_t model_fingerprint(const DemModel<3>& model) noexcept;
std::uint64_t model_fingerprint(const BarModel& model) noexcept;
std::uint64_t model_fingerprint(const PlateModel& model) noexcept;
std::uint64_t model_fingerprint(const CoupledModel& model) noexcept;
std::uint64_t model_fingerprint(const Coupled2dModel& model) noexcept;

// ---- snapshots -------------------------------------------------------------------
//
// Layout (every integer in the writer's byte order, which the reader checks):
//   offset  size  field
//        0     8  magic "XFDEMSNP"
//        8     4  format version (kSnapshotVersion)
//       12     4  header size in bytes (kSnapshotHeaderBytes)
//       16     4  byte-order tag 0x01020304
//       20     1  sizeof(double)
//       21     1  state kind (SnapshotKind)
//       22     2  zero
//       24     8  layout hash of the state
//       32     8  model tag (0 when the caller passes none)
//       40     8  payload size in bytes
//       48     8  payload checksum = state hash
//       56     8  FNV-1a of bytes 0..55
//       64     …  payload: the raw bytes of every field in visitor order

inline constexpr std::uint32_t kSnapshotVersion = 2;  // 2: the energy ledgers
inline constexpr std::size_t kSnapshotHeaderBytes = 64;

enum class SnapshotKind : std::uint8_t { dem1 = 1, dem2 = 2, dem3 = 3, bar = 4, coupled = 5, plate = 6, coupled2d = 7 };

enum class SnapshotStatus : std::uint8_t {
  ok,
  buffer_too_small,   ///< save: the buffer holds fewer than snapshot_size() bytes; nothing written
  truncated,          ///< restore: fewer bytes than the header (or the header's payload size) needs
  not_a_snapshot,     ///< restore: the magic is wrong
  corrupted_header,   ///< restore: the header checksum does not match
  unsupported_version,///< restore: another format version
  foreign_byte_order, ///< restore: written on a machine of the other endianness
  foreign_precision,  ///< restore: written with another sizeof(double)
  other_state_kind,   ///< restore: a snapshot of another kind of state (bar vs particles, 2D vs 3D, …)
  other_layout,       ///< restore: the target state's fields or sizes differ (another scene or model size)
  other_model,        ///< restore: the model tags differ (another scene with the same sizes)
  corrupted_payload,  ///< restore: the payload checksum does not match, or an index or count in it is
                      ///< out of range for the target state (history slot, pair list, a 0/1 flag)
  io_error,           ///< file helpers: the file could not be read or written
};

const char* snapshot_status_name(SnapshotStatus status) noexcept;

struct SnapshotResult {
  SnapshotStatus status = SnapshotStatus::ok;
  std::size_t bytes = 0;   ///< bytes written (save) or read (restore)
  char message[256] = {};  ///< what was refused and why, with the numbers involved
  [[nodiscard]] bool ok() const noexcept { return status == SnapshotStatus::ok; }
};

/// Bytes a snapshot of this state takes (header + payload).
std::size_t snapshot_size(const DemState<1>& state) noexcept;
std::size_t snapshot_size(const DemState<2>& state) noexcept;
std::size_t snapshot_size(const DemState<3>& state) noexcept;
std::size_t snapshot_size(const BarState& state) noexcept;
std::size_t snapshot_size(const PlateState& state) noexcept;
std::size_t snapshot_size(const CoupledState& state) noexcept;
std::size_t snapshot_size(const Coupled2dState& state) noexcept;

/// Writes a snapshot into the first snapshot_size(state) bytes of `buffer`.
/// `model_tag` (model_fingerprint(model), or 0) is stored for restore to check.
SnapshotResult save_snapshot(const DemState<1>& state, std::span<std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult save_snapshot(const DemState<2>& state, std::span<std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult save_snapshot(const DemState<3>& state, std::span<std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult save_snapshot(const BarState& state, std::span<std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult save_snapshot(const PlateState& state, std::span<std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult save_snapshot(const CoupledState& state, std::span<std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult save_snapshot(const Coupled2dState& state, std::span<std::byte> buffer, std::uint64_t model_tag = 0) noexcept;

/// Restores a snapshot into `state`, which must have been built by the same
/// model (its arrays give the expected layout). Everything is checked before a
/// byte of the state is written: on any refusal the state is left untouched.
/// Bytes after the snapshot in `buffer` are ignored. `model_tag` must equal the
/// one the snapshot was saved with.
SnapshotResult restore_snapshot(DemState<1>& state, std::span<const std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult restore_snapshot(DemState<2>& state, std::span<const std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult restore_snapshot(DemState<3>& state, std::span<const std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult restore_snapshot(BarState& state, std::span<const std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult restore_snapshot(PlateState& state, std::span<const std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult restore_snapshot(CoupledState& state, std::span<const std::byte> buffer, std::uint64_t model_tag = 0) noexcept;
SnapshotResult restore_snapshot(Coupled2dState& state, std::span<const std::byte> buffer, std::uint64_t model_tag = 0) noexcept;

// ---- file helpers (tools only: these allocate a buffer and touch the file system) --

SnapshotResult save_snapshot_file(const char* path, const DemState<1>& state, std::uint64_t model_tag = 0);
SnapshotResult save_snapshot_file(const char* path, const DemState<2>& state, std::uint64_t model_tag = 0);
SnapshotResult save_snapshot_file(const char* path, const DemState<3>& state, std::uint64_t model_tag = 0);
SnapshotResult save_snapshot_file(const char* path, const BarState& state, std::uint64_t model_tag = 0);
SnapshotResult save_snapshot_file(const char* path, const PlateState& state, std::uint64_t model_tag = 0);
SnapshotResult save_snapshot_file(const char* path, const CoupledState& state, std::uint64_t model_tag = 0);
SnapshotResult save_snapshot_file(const char* path, const Coupled2dState& state, std::uint64_t model_tag = 0);

SnapshotResult restore_snapshot_file(const char* path, DemState<1>& state, std::uint64_t model_tag = 0);
SnapshotResult restore_snapshot_file(const char* path, DemState<2>& state, std::uint64_t model_tag = 0);
SnapshotResult restore_snapshot_file(const char* path, DemState<3>& state, std::uint64_t model_tag = 0);
SnapshotResult restore_snapshot_file(const char* path, BarState& state, std::uint64_t model_tag = 0);
SnapshotResult restore_snapshot_file(const char* path, PlateState& state, std::uint64_t model_tag = 0);
SnapshotResult restore_snapshot_file(const char* path, CoupledState& state, std::uint64_t model_tag = 0);
SnapshotResult restore_snapshot_file(const char* path, Coupled2dState& state, std::uint64_t model_tag = 0);

}  // namespace xfdem
