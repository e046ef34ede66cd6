// State hashing and snapshots (xfdem/state_io.hpp). One template does the work
// for every kind of state by walking its visitor; the overloads below only pick
// the instantiation. Nothing here allocates except the file helpers.
#include "xfdem/state_io.hpp"

#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <vector>

namespace xfdem {
namespace {

// ---- walking -----------------------------------------------------------------

/// Calls f(part, name, bytes, count, element_size) for every field. The states'
/// visitors are non-const; this walk only reads through them unless the caller
/// passes a mutable state.
template <class State, class F>
void walk(const State& state, F&& f) {
  for_each_field(const_cast<State&>(state), [&](const char* part, const char* name, auto* data, std::size_t count) {
    f(part, name, reinterpret_cast<std::byte*>(data), count, sizeof(*data));
  });
}

std::uint64_t mix_u64(std::uint64_t hash, std::uint64_t value) noexcept {
  std::byte bytes[8];
  for (int k = 0; k < 8; ++k) bytes[k] = static_cast<std::byte>((value >> (8 * k)) & 0xffu);  // little-endian
  return fnv1a(bytes, 8, hash);
}

std::uint64_t mix_text(std::uint64_t hash, const char* text) noexcept {
  return fnv1a(reinterpret_cast<const std::byte*>(text), std::strlen(text), hash);
}

template <class State>
std::uint64_t state_hash_of(const State& state) noexcept {
  std::uint64_t hash = kFnvOffset;
  walk(state, [&](const char*, const char*, const std::byte* data, std::size_t count, std::size_t size) {
    if (count > 0) hash = fnv1a(data, count * size, hash);
  });
  return hash;
}

template <class State>
std::uint64_t layout_hash_of(const State& state) noexcept {
  std::uint64_t hash = kFnvOffset;
  walk(state, [&](const char* part, const char* name, const std::byte*, std::size_t count, std::size_t size) {
    hash = mix_text(hash, part);
    hash = mix_text(hash, ".");
    hash = mix_text(hash, name);
    const std::byte nul{0};
    hash = fnv1a(&nul, 1, hash);
    hash = mix_u64(hash, count);
    hash = mix_u64(hash, size);
  });
  return hash;
}

template <class State>
std::size_t field_count_of(const State& state) noexcept {
  std::size_t n = 0;
  walk(state, [&](const char*, const char*, const std::byte*, std::size_t, std::size_t) { ++n; });
  return n;
}

template <class State>
std::size_t field_hashes_of(const State& state, std::span<std::uint64_t> out) noexcept {
  std::size_t k = 0;
  walk(state, [&](const char*, const char*, const std::byte* data, std::size_t count, std::size_t size) {
    if (k < out.size()) out[k] = count > 0 ? fnv1a(data, count * size) : kFnvOffset;
    ++k;
  });
  return k;
}

template <class State>
std::size_t payload_bytes_of(const State& state) noexcept {
  std::size_t bytes = 0;
  walk(state, [&](const char*, const char*, const std::byte*, std::size_t count, std::size_t size) {
    bytes += count * size;
  });
  return bytes;
}

template <class State>
const char* field_name_of(const State& state, std::size_t wanted, char* buffer, int buffer_size) noexcept {
  if (buffer_size <= 0) return buffer;
  const char* part = nullptr;
  const char* name = nullptr;
  std::size_t k = 0;
  walk(state, [&](const char* p, const char* n, const std::byte*, std::size_t, std::size_t) {
    if (k++ == wanted) part = p, name = n;
  });
  if (name == nullptr) {
    std::snprintf(buffer, static_cast<std::size_t>(buffer_size), "?");
    return buffer;
  }
  // Which occurrence of (part, name) it is, and how many there are.
  int occurrence = 0, total = 0;
  k = 0;
  walk(state, [&](const char* p, const char* n, const std::byte*, std::size_t, std::size_t) {
    if (std::strcmp(p, part) == 0 && std::strcmp(n, name) == 0) {
      if (k < wanted) ++occurrence;
      ++total;
    }
    ++k;
  });
  const char* dot = part[0] != '\0' ? "." : "";
  if (total > 1)
    std::snprintf(buffer, static_cast<std::size_t>(buffer_size), "%s%s%s[%d]", part, dot, name, occurrence);
  else
    std::snprintf(buffer, static_cast<std::size_t>(buffer_size), "%s%s%s", part, dot, name);
  return buffer;
}

// ---- model fingerprints ------------------------------------------------------------

std::uint64_t mix_double(std::uint64_t hash, double value) noexcept {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof(bits));
  return mix_u64(hash, bits);
}
std::uint64_t mix_doubles(std::uint64_t hash, const std::vector<double>& values) noexcept {
  hash = mix_u64(hash, values.size());
  for (double v : values) hash = mix_double(hash, v);
  return hash;
}

template <int D>
std::uint64_t dem_fingerprint(const DemModel<D>& m) noexcept {
  std::uint64_t h = mix_u64(kFnvOffset, static_cast<std::uint64_t>(D));
  h = mix_u64(h, static_cast<std::uint64_t>(m.n));
  h = mix_doubles(h, m.mass);
  h = mix_doubles(h, m.radius);
  h = mix_doubles(h, m.stiffness);
  h = mix_doubles(h, m.plane_eta);
  h = mix_u64(h, m.plane_point.size());
  for (std::size_t p = 0; p < m.plane_point.size(); ++p)
    for (int d = 0; d < D; ++d) h = mix_double(mix_double(h, m.plane_point[p][d]), m.plane_normal[p][d]);
  for (int d = 0; d < D; ++d) h = mix_double(h, m.gravity[d]);
  h = mix_u64(h, static_cast<std::uint64_t>(m.law));
  h = mix_double(h, m.damping_ratio);
  h = mix_u64(h, static_cast<std::uint64_t>(m.integrator));
  h = mix_double(h, m.dt);
  h = mix_double(h, m.skin);
  h = mix_double(h, m.cell_size);
  h = mix_u64(h, static_cast<std::uint64_t>(m.capacities.max_pairs));
  h = mix_u64(h, static_cast<std::uint64_t>(m.capacities.max_neighbors_per_particle));
  h = mix_u64(h, static_cast<std::uint64_t>(m.capacities.max_grid_cells));
  h = mix_u64(h, static_cast<std::uint64_t>(m.capacities.max_events_per_step));
  h = mix_u64(h, static_cast<std::uint64_t>(m.features.broad_phase));
  // The split into parts fixes the order of the sums across the parts.
  h = mix_u64(h, static_cast<std::uint64_t>(m.parts));
  h = mix_u64(h, static_cast<std::uint64_t>(m.split));
  if (m.law == ContactLaw::hertz) {  // the materials (other laws' fingerprints unchanged)
    h = mix_doubles(mix_doubles(h, m.hertz_inv_e), m.hertz_inv_g);
    h = mix_doubles(mix_doubles(h, m.plane_inv_e), m.plane_inv_g);
    h = mix_double(h, m.hertz_damping);
  }
  if (!m.inv_inertia.empty()) {  // rotating models: the tangential law (frictionless fingerprints unchanged)
    h = mix_doubles(h, m.inv_inertia);
    h = mix_double(mix_double(mix_double(h, m.friction), m.tangential_ratio), m.rolling_friction);
  }
  return h;
}

// ---- snapshot header ----------------------------------------------------------------

constexpr char kMagic[8] = {'X', 'F', 'D', 'E', 'M', 'S', 'N', 'P'};
constexpr std::uint32_t kByteOrderTag = 0x01020304u;
constexpr std::uint32_t kByteOrderSwapped = 0x04030201u;

struct Header {
  std::uint32_t version = 0, header_bytes = 0, byte_order = 0;
  std::uint8_t real_bytes = 0, kind = 0;
  std::uint64_t layout = 0, model_tag = 0, payload_bytes = 0, checksum = 0, header_checksum = 0;
};

template <class T>
void put(std::byte* at, T value) noexcept {
  std::memcpy(at, &value, sizeof(T));
}
template <class T>
T get(const std::byte* at) noexcept {
  T value;
  std::memcpy(&value, at, sizeof(T));
  return value;
}

void write_header(std::byte* out, const Header& h) noexcept {
  std::memset(out, 0, kSnapshotHeaderBytes);
  std::memcpy(out, kMagic, 8);
  put(out + 8, h.version);
  put(out + 12, h.header_bytes);
  put(out + 16, h.byte_order);
  put(out + 20, h.real_bytes);
  put(out + 21, h.kind);
  put(out + 24, h.layout);
  put(out + 32, h.model_tag);
  put(out + 40, h.payload_bytes);
  put(out + 48, h.checksum);
  put(out + 56, fnv1a(out, 56));
}

Header read_header(const std::byte* in) noexcept {
  Header h;
  h.version = get<std::uint32_t>(in + 8);
  h.header_bytes = get<std::uint32_t>(in + 12);
  h.byte_order = get<std::uint32_t>(in + 16);
  h.real_bytes = get<std::uint8_t>(in + 20);
  h.kind = get<std::uint8_t>(in + 21);
  h.layout = get<std::uint64_t>(in + 24);
  h.model_tag = get<std::uint64_t>(in + 32);
  h.payload_bytes = get<std::uint64_t>(in + 40);
  h.checksum = get<std::uint64_t>(in + 48);
  h.header_checksum = get<std::uint64_t>(in + 56);
  return h;
}

const char* kind_name(std::uint8_t kind) noexcept {
  switch (kind) {
    case 1: return "DemState<1>";
    case 2: return "DemState<2>";
    case 3: return "DemState<3>";
    case 4: return "BarState";
    case 5: return "CoupledState";
    case 6: return "PlateState";
    case 7: return "Coupled2dState";
    default: return "unknown";
  }
}

template <class State>
constexpr SnapshotKind kind_of() noexcept;
template <>
constexpr SnapshotKind kind_of<DemState<1>>() noexcept { return SnapshotKind::dem1; }
template <>
constexpr SnapshotKind kind_of<DemState<2>>() noexcept { return SnapshotKind::dem2; }
template <>
constexpr SnapshotKind kind_of<DemState<3>>() noexcept { return SnapshotKind::dem3; }
template <>
constexpr SnapshotKind kind_of<BarState>() noexcept { return SnapshotKind::bar; }
template <>
constexpr SnapshotKind kind_of<CoupledState>() noexcept { return SnapshotKind::coupled; }
template <>
constexpr SnapshotKind kind_of<PlateState>() noexcept { return SnapshotKind::plate; }
template <>
constexpr SnapshotKind kind_of<Coupled2dState>() noexcept { return SnapshotKind::coupled2d; }

SnapshotResult result(SnapshotStatus status, std::size_t bytes, const char* format, ...)
    __attribute__((format(printf, 3, 4)));
SnapshotResult result(SnapshotStatus status, std::size_t bytes, const char* format, ...) {
  SnapshotResult r;
  r.status = status;
  r.bytes = bytes;
  va_list args;
  va_start(args, format);
  std::vsnprintf(r.message, sizeof(r.message), format, args);
  va_end(args);
  return r;
}

using ull = unsigned long long;

template <class State>
SnapshotResult save_of(const State& state, std::span<std::byte> buffer, std::uint64_t model_tag) noexcept {
  const std::size_t payload = payload_bytes_of(state);
  const std::size_t total = kSnapshotHeaderBytes + payload;
  if (buffer.size() < total)
    return result(SnapshotStatus::buffer_too_small, 0, "snapshot needs %llu bytes, the buffer holds %llu",
                  static_cast<ull>(total), static_cast<ull>(buffer.size()));
  std::byte* out = buffer.data() + kSnapshotHeaderBytes;
  walk(state, [&](const char*, const char*, const std::byte* data, std::size_t count, std::size_t size) {
    if (count == 0) return;
    std::memcpy(out, data, count * size);
    out += count * size;
  });
  Header h;
  h.version = kSnapshotVersion;
  h.header_bytes = static_cast<std::uint32_t>(kSnapshotHeaderBytes);
  h.byte_order = kByteOrderTag;
  h.real_bytes = static_cast<std::uint8_t>(sizeof(double));
  h.kind = static_cast<std::uint8_t>(kind_of<State>());
  h.layout = layout_hash_of(state);
  h.model_tag = model_tag;
  h.payload_bytes = payload;
  h.checksum = fnv1a(buffer.data() + kSnapshotHeaderBytes, payload);
  write_header(buffer.data(), h);
  return result(SnapshotStatus::ok, total, "saved %llu bytes", static_cast<ull>(total));
}

/// The payload's integer fields that the steppers use as indices and counts,
/// checked against the target state's sizes before anything is copied: a
/// payload whose checksum matches can still hold values no step produces (a
/// file edited and re-checksummed, or a writer's bug), and stepping from them
/// would index out of bounds. Returns true when every value is in range, else
/// false with the first value out of range named in `message`.
template <class State>
bool payload_values_ok(const State& state, const std::byte* payload, char* message, std::size_t message_size) noexcept {
  std::size_t particles = 0, pair_slots = 0;
  bool seen_x = false;
  std::int32_t pair_count = 0;
  const std::byte* pair_i = nullptr;
  const std::byte* pair_j = nullptr;
  const char* bad = nullptr;
  long long bad_value = 0;
  const std::byte* at = payload;
  auto i32 = [](const std::byte* p) { return get<std::int32_t>(p); };
  walk(state, [&](const char*, const char* name, const std::byte*, std::size_t count, std::size_t size) {
    const std::byte* here = at;
    at += count * size;
    if (bad != nullptr) return;
    auto in = [&](long long value, long long lo, long long hi) {
      if (value < lo || value > hi) bad = name, bad_value = value;
    };
    if (std::strcmp(name, "x") == 0 && !seen_x) {
      particles = count;
      seen_x = true;
    } else if (std::strcmp(name, "history_head") == 0) {
      in(i32(here), 0, 3);
    } else if (std::strcmp(name, "history_count") == 0) {
      in(i32(here), 0, 4);
    } else if (std::strcmp(name, "pair_i") == 0) {
      pair_i = here;
      pair_slots = count;
    } else if (std::strcmp(name, "pair_j") == 0) {
      pair_j = here;
    } else if (std::strcmp(name, "pair_count") == 0) {
      pair_count = i32(here);
    } else if (std::strcmp(name, "pairs_valid") == 0 || std::strcmp(name, "interface_closed") == 0 ||
               std::strcmp(name, "energy_exceeded") == 0) {
      in(i32(here), 0, 1);
    }
  });
  if (bad == nullptr && pair_i != nullptr) {
    if (pair_count < 0 || static_cast<std::size_t>(pair_count) > pair_slots) {
      bad = "pair_count", bad_value = pair_count;
    } else {
      for (std::int32_t k = 0; k < pair_count && bad == nullptr; ++k) {
        const std::int32_t i = i32(pair_i + 4 * static_cast<std::size_t>(k));
        const std::int32_t j = i32(pair_j + 4 * static_cast<std::size_t>(k));
        if (i < 0 || static_cast<std::size_t>(i) >= particles) bad = "pair_i", bad_value = i;
        else if (j < 0 || static_cast<std::size_t>(j) >= particles) bad = "pair_j", bad_value = j;
      }
    }
  }
  if (bad == nullptr) return true;
  std::snprintf(message, message_size, "corrupted snapshot: field '%s' holds %lld, out of range for this state", bad,
                bad_value);
  return false;
}

template <class State>
SnapshotResult restore_of(State& state, std::span<const std::byte> buffer, std::uint64_t model_tag) noexcept {
  const std::size_t have = buffer.size();
  if (have < kSnapshotHeaderBytes)
    return result(SnapshotStatus::truncated, 0, "truncated snapshot: %llu bytes, shorter than the %llu-byte header",
                  static_cast<ull>(have), static_cast<ull>(kSnapshotHeaderBytes));
  const std::byte* in = buffer.data();
  if (std::memcmp(in, kMagic, 8) != 0)
    return result(SnapshotStatus::not_a_snapshot, 0, "not an xfdem snapshot: the first 8 bytes are not \"XFDEMSNP\"");
  const Header h = read_header(in);
  if (fnv1a(in, 56) != h.header_checksum)
    return result(SnapshotStatus::corrupted_header, 0, "corrupted snapshot: the header checksum does not match");
  // A byte-swapped writer shows its version swapped too: judge the byte order first.
  if (h.byte_order == kByteOrderSwapped)
    return result(SnapshotStatus::foreign_byte_order, 0,
                  "snapshot written on a machine of the other byte order (endianness); this one cannot read it");
  if (h.byte_order != kByteOrderTag)
    return result(SnapshotStatus::corrupted_header, 0, "corrupted snapshot: unknown byte-order tag 0x%08x",
                  static_cast<unsigned>(h.byte_order));
  if (h.version != kSnapshotVersion || h.header_bytes != kSnapshotHeaderBytes)
    return result(SnapshotStatus::unsupported_version, 0,
                  "snapshot format version %u (header %u bytes); this build reads version %u (header %u bytes)",
                  static_cast<unsigned>(h.version), static_cast<unsigned>(h.header_bytes),
                  static_cast<unsigned>(kSnapshotVersion), static_cast<unsigned>(kSnapshotHeaderBytes));
  if (h.real_bytes != sizeof(double))
    return result(SnapshotStatus::foreign_precision, 0,
                  "snapshot written with %u-byte reals; this build uses %u-byte doubles",
                  static_cast<unsigned>(h.real_bytes), static_cast<unsigned>(sizeof(double)));
  const auto want_kind = static_cast<std::uint8_t>(kind_of<State>());
  if (h.kind != want_kind)
    return result(SnapshotStatus::other_state_kind, 0, "snapshot of a %s cannot be restored into a %s",
                  kind_name(h.kind), kind_name(want_kind));
  const std::uint64_t layout = layout_hash_of(state);
  const std::size_t payload = payload_bytes_of(state);
  if (h.layout != layout)
    return result(SnapshotStatus::other_layout, 0,
                  "snapshot of another state layout (another scene or model size): layout hash %016llx and "
                  "%llu payload bytes, the target state has %016llx and %llu",
                  static_cast<ull>(h.layout), static_cast<ull>(h.payload_bytes), static_cast<ull>(layout),
                  static_cast<ull>(payload));
  if (h.model_tag != model_tag)
    return result(SnapshotStatus::other_model, 0,
                  "snapshot of another model: model tag %016llx, the target's model has %016llx",
                  static_cast<ull>(h.model_tag), static_cast<ull>(model_tag));
  if (h.payload_bytes != payload)
    return result(SnapshotStatus::corrupted_header, 0,
                  "corrupted snapshot: header gives %llu payload bytes, its layout has %llu",
                  static_cast<ull>(h.payload_bytes), static_cast<ull>(payload));
  if (have - kSnapshotHeaderBytes < payload)
    return result(SnapshotStatus::truncated, 0, "truncated snapshot: %llu bytes, the header and payload need %llu",
                  static_cast<ull>(have), static_cast<ull>(kSnapshotHeaderBytes + payload));
  const std::uint64_t checksum = fnv1a(in + kSnapshotHeaderBytes, payload);
  if (checksum != h.checksum)
    return result(SnapshotStatus::corrupted_payload, 0,
                  "corrupted snapshot: payload checksum %016llx, the header says %016llx",
                  static_cast<ull>(checksum), static_cast<ull>(h.checksum));
  char message[sizeof(SnapshotResult{}.message)];
  if (!payload_values_ok(state, in + kSnapshotHeaderBytes, message, sizeof(message)))
    return result(SnapshotStatus::corrupted_payload, 0, "%s", message);
  // Everything checked: only now is the state written.
  const std::byte* from = in + kSnapshotHeaderBytes;
  for_each_field(state, [&](const char*, const char*, auto* data, std::size_t count) {
    const std::size_t bytes = count * sizeof(*data);
    if (bytes == 0) return;
    std::memcpy(data, from, bytes);
    from += bytes;
  });
  return result(SnapshotStatus::ok, kSnapshotHeaderBytes + payload, "restored %llu bytes",
                static_cast<ull>(kSnapshotHeaderBytes + payload));
}

template <class State>
SnapshotResult save_file_of(const char* path, const State& state, std::uint64_t model_tag) {
  std::vector<std::byte> bytes(kSnapshotHeaderBytes + payload_bytes_of(state));
  SnapshotResult r = save_of(state, std::span<std::byte>(bytes), model_tag);
  if (!r.ok()) return r;
  std::FILE* file = std::fopen(path, "wb");
  if (file == nullptr) return result(SnapshotStatus::io_error, 0, "cannot open '%s' for writing", path);
  const std::size_t written = std::fwrite(bytes.data(), 1, bytes.size(), file);
  const bool closed = std::fclose(file) == 0;
  if (written != bytes.size() || !closed)
    return result(SnapshotStatus::io_error, 0, "cannot write '%s' (%llu of %llu bytes written)", path,
                  static_cast<ull>(written), static_cast<ull>(bytes.size()));
  return r;
}

template <class State>
SnapshotResult restore_file_of(const char* path, State& state, std::uint64_t model_tag) {
  std::FILE* file = std::fopen(path, "rb");
  if (file == nullptr) return result(SnapshotStatus::io_error, 0, "cannot open '%s' for reading", path);
  std::vector<std::byte> bytes;
  std::byte chunk[65536];
  std::size_t got;
  while ((got = std::fread(chunk, 1, sizeof(chunk), file)) > 0) bytes.insert(bytes.end(), chunk, chunk + got);
  const bool failed = std::ferror(file) != 0;
  std::fclose(file);
  if (failed) return result(SnapshotStatus::io_error, 0, "cannot read '%s'", path);
  return restore_of(state, std::span<const std::byte>(bytes), model_tag);
}

}  // namespace

const char* snapshot_status_name(SnapshotStatus status) noexcept {
  switch (status) {
    case SnapshotStatus::ok: return "ok";
    case SnapshotStatus::buffer_too_small: return "buffer_too_small";
    case SnapshotStatus::truncated: return "truncated";
    case SnapshotStatus::not_a_snapshot: return "not_a_snapshot";
    case SnapshotStatus::corrupted_header: return "corrupted_header";
    case SnapshotStatus::unsupported_version: return "unsupported_version";
    case SnapshotStatus::foreign_byte_order: return "foreign_byte_order";
    case SnapshotStatus::foreign_precision: return "foreign_precision";
    case SnapshotStatus::other_state_kind: return "other_state_kind";
    case SnapshotStatus::other_layout: return "other_layout";
    case SnapshotStatus::other_model: return "other_model";
    case SnapshotStatus::corrupted_payload: return "corrupted_payload";
    case SnapshotStatus::io_error: return "io_error";
  }
  return "unknown";
}

std::uint64_t model_fingerprint(const DemModel<1>& model) noexcept { return dem_fingerprint(model); }
std::uint64_t model_fingerprint(const DemModel<2>& model) noexcept { return dem_fingerprint(model); }
std::uint64_t model_fingerprint(const DemModel<3>& model) noexcept { return dem_fingerprint(model); }

std::uint64_t model_fingerprint(const BarModel& model) noexcept {
  const BarDesc& d = model.desc;
  std::uint64_t h = mix_u64(kFnvOffset, 0x4241u);  // "BA"
  for (double v : {d.length, d.youngs_modulus, d.area, d.density, d.base_stiffness, d.beta, d.gamma, d.dt,
                   d.tip_amplitude, d.tip_duration})
    h = mix_double(h, v);
  for (int v : {d.elements, static_cast<int>(d.method), static_cast<int>(d.base), static_cast<int>(d.tip_load),
                d.max_active_set_iterations, model.dofs})
    h = mix_u64(h, static_cast<std::uint64_t>(v));
  h = mix_u64(h, d.interface.has_value() ? 1u : 0u);
  if (d.interface) {
    h = mix_double(h, d.interface->position);
    h = mix_double(h, d.interface->stiffness);
    h = mix_u64(h, static_cast<std::uint64_t>(d.interface->behaviour));
  }
  return h;
}

std::uint64_t model_fingerprint(const PlateModel& model) noexcept {
  const PlateDesc& d = model.desc;
  std::uint64_t h = mix_u64(kFnvOffset, 0x504cu);  // "PL"
  for (double v : {d.min[0], d.min[1], d.max[0], d.max[1], d.thickness, d.youngs_modulus, d.poisson_ratio, d.density,
                   d.gravity[0], d.gravity[1], d.beta, d.gamma, d.dt})
    h = mix_double(h, v);
  for (int v : {d.cells[0], d.cells[1], static_cast<int>(d.plane), static_cast<int>(d.analysis),
                static_cast<int>(d.self_weight), model.dofs})
    h = mix_u64(h, static_cast<std::uint64_t>(v));
  for (const PlateSupport& s : d.supports)
    h = mix_u64(h, static_cast<std::uint64_t>(s.edge) | (s.fix[0] ? 16u : 0u) | (s.fix[1] ? 32u : 0u) |
                       (s.absorbing ? 64u : 0u));
  for (const PlatePrescribed& p : d.prescribed) {
    for (double v : {p.at[0], p.at[1], p.displacement[0], p.displacement[1]}) h = mix_double(h, v);
    // A time shape (step, the default, leaves earlier fingerprints unchanged).
    if (p.shape != PlatePrescribedShape::step)
      h = mix_double(mix_u64(h, 0x5000u | static_cast<std::uint64_t>(p.shape)), p.duration);
  }
  for (const PlateLoad& l : d.loads) {
    h = mix_u64(h, static_cast<std::uint64_t>(l.kind) | (static_cast<std::uint64_t>(l.edge) << 4) |
                       (static_cast<std::uint64_t>(l.shape) << 8));
    for (double v : {l.at[0], l.at[1], l.value[0], l.value[1], l.duration}) h = mix_double(h, v);
  }
  if (!d.absorb_enrichment) h = mix_u64(h, 0xab5u);  // the default leaves earlier fingerprints unchanged
  for (const PlateDiscontinuity& q : d.discontinuities) {  // none: the hash of an uncut plate is unchanged
    h = mix_u64(h, static_cast<std::uint64_t>(q.kind) | (static_cast<std::uint64_t>(q.shape) << 4) |
                       (static_cast<std::uint64_t>(q.faces) << 8) | (q.enrich ? 1u << 12 : 0u));
    for (const auto& p : q.points) h = mix_double(mix_double(h, p[0]), p[1]);
    for (double v : {q.centre[0], q.centre[1], q.radius, q.stiffness[0], q.stiffness[1], q.material.youngs_modulus,
                     q.material.poisson_ratio, q.material.density})
      h = mix_double(h, v);
  }
  if (!model.tips.empty()) h = mix_double(h, d.tip_radius);  // only with a tip: other plates' hashes unchanged
  return h;
}

std::uint64_t model_fingerprint(const CoupledModel& model) noexcept {
  std::uint64_t h = mix_u64(kFnvOffset, 0x4350u);  // "CP"
  h = mix_u64(h, dem_fingerprint(model.dem));
  h = mix_u64(h, model_fingerprint(model.bar));
  h = mix_u64(h, static_cast<std::uint64_t>(model.substeps));
  h = mix_double(h, model.dt);
  h = mix_u64(h, static_cast<std::uint64_t>(model.top_plane));
  return h;
}

std::uint64_t model_fingerprint(const Coupled2dModel& model) noexcept {
  std::uint64_t h = mix_u64(kFnvOffset, 0x4332u);  // "C2"
  h = mix_u64(h, dem_fingerprint(model.dem));
  h = mix_u64(h, model_fingerprint(model.plate));
  h = mix_u64(h, static_cast<std::uint64_t>(model.substeps));
  h = mix_double(h, model.dt);
  // The boundary's broad phase (its bins fix the order of a disk's contacts).
  h = mix_double(mix_double(h, model.boundary.reach), model.boundary.allowance);
  return h;
}

// ---- the overloads -------------------------------------------------------------------

#define XFDEM_STATE_IO_OVERLOADS(State)                                                                      \
  std::uint64_t state_hash(const State& state) noexcept { return state_hash_of(state); }                   \
  std::uint64_t layout_hash(const State& state) noexcept { return layout_hash_of(state); }                 \
  std::size_t field_count(const State& state) noexcept { return field_count_of(state); }                   \
  std::size_t field_hashes(const State& state, std::span<std::uint64_t> out) noexcept {                    \
    return field_hashes_of(state, out);                                                                      \
  }                                                                                                          \
  const char* field_name(const State& state, std::size_t k, char* buffer, int buffer_size) noexcept {      \
    return field_name_of(state, k, buffer, buffer_size);                                                     \
  }                                                                                                          \
  std::size_t snapshot_size(const State& state) noexcept {                                                 \
    return kSnapshotHeaderBytes + payload_bytes_of(state);                                                   \
  }                                                                                                          \
  SnapshotResult save_snapshot(const State& state, std::span<std::byte> buffer, std::uint64_t model_tag) noexcept { \
    return save_of(state, buffer, model_tag);                                                                \
  }                                                                                                          \
  SnapshotResult restore_snapshot(State& state, std::span<const std::byte> buffer,                         \
                                  std::uint64_t model_tag) noexcept {                                        \
    return restore_of(state, buffer, model_tag);                                                             \
  }                                                                                                          \
  SnapshotResult save_snapshot_file(const char* path, const State& state, std::uint64_t model_tag) {       \
    return save_file_of(path, state, model_tag);                                                             \
  }                                                                                                          \
  SnapshotResult restore_snapshot_file(const char* path, State& state, std::uint64_t model_tag) {          \
    return restore_file_of(path, state, model_tag);                                                          \
  }

XFDEM_STATE_IO_OVERLOADS(DemState<1>)
XFDEM_STATE_IO_OVERLOADS(DemState<2>)
XFDEM_STATE_IO_OVERLOADS(DemState<3>)
XFDEM_STATE_IO_OVERLOADS(BarState)
XFDEM_STATE_IO_OVERLOADS(CoupledState)
XFDEM_STATE_IO_OVERLOADS(PlateState)
XFDEM_STATE_IO_OVERLOADS(Coupled2dState)

#undef XFDEM_STATE_IO_OVERLOADS

}  // namespace xfdem
