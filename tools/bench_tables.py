#!/usr/bin/env python3
"""Runs xfdem_bench and prints the tables of docs/benchmarks.md from one run.

Every table there is a median of repeated Google Benchmark runs; this script
runs each table's benchmarks (same filters as the commands the page gives),
reads the JSON, and prints the markdown rows, so a refresh of the page is one
command:

    /usr/bin/python3 tools/bench_tables.py [--build build/release] [--repetitions 5]
        [--tables drop,packing,bar,bar_events,coupled,features,energy_check,workers,threshold]

Times are CPU time per step unless the table says wall time (the packings run
with UseRealTime). Standard library only.
"""
import argparse
import json
import subprocess
import sys

UNIT_NS = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}


def run(bench, pattern, repetitions):
    """Medians of `repetitions` runs of the benchmarks matching `pattern`, by run name."""
    result = subprocess.run(
        [bench, f"--benchmark_filter={pattern}", f"--benchmark_repetitions={repetitions}",
         "--benchmark_report_aggregates_only=true", "--benchmark_format=json"],
        check=True, capture_output=True, text=True)
    medians = {}
    for b in json.loads(result.stdout)["benchmarks"]:
        if b.get("aggregate_name") == "median":
            b["cpu_ns"] = b["cpu_time"] * UNIT_NS[b["time_unit"]]
            b["real_ns"] = b["real_time"] * UNIT_NS[b["time_unit"]]
            medians[b["run_name"]] = b
    return medians


def time_text(ns):
    """ns, µs or ms with three significant digits."""
    for unit, scale in (("ns", 1.0), ("µs", 1e3), ("ms", 1e6)):
        if ns < 1000 * scale or unit == "ms":
            value = ns / scale
            text = f"{value:#.3g}" if value < 100 else f"{value:.0f}"
            return f"{text.rstrip('.')} {unit}"
    return f"{ns} ns"


def table(header, rows):
    print("| " + " | ".join(header) + " |")
    print("|" + "|".join("---" if k == 0 else "---:" for k in range(len(header))) + "|")
    for row in rows:
        print("| " + " | ".join(str(c) for c in row) + " |")
    print()


def drop(bench, reps):
    r = run(bench, "BM_DemDrop", reps)
    print("### V1 drop test (ns per step)\n")
    table(["integrator", "ns per step"],
          [[k, f"{r['BM_DemDrop/' + k]['cpu_ns']:.1f}"] for k in ("abm4", "abm4_events", "verlet")])


def packing(bench, reps):
    r = run(bench, "BM_DemPacking/(verlet|abm4|verlet_skin_0.2r)/[0-9]+/1/", reps)
    print("### Dense 3D packing, one worker\n")
    rows = []
    for variant, label in (("verlet", "verlet"), ("abm4", "abm4"), ("verlet_skin_0.2r", "verlet, skin 0.2 r")):
        for n in (1000, 10000, 100000):
            b = r.get(f"BM_DemPacking/{variant}/{n}/1/-1/real_time")
            if b:
                rows.append([label, f"{n:,}".replace(",", " "), f"{b['per_particle_step'] * 1e9:.1f}",
                             f"{b['contacts_per_particle']:.2f}", f"{b['pairs_listed_per_particle']:.2f}",
                             f"{b['rebuilds_per_step']:.4g}"])
    table(["integrator", "N", "ns per particle-step", "contacts per particle", "listed pairs per particle",
           "list rebuilds per step"], rows)


def bar(bench, reps):
    r = run(bench, "BM_Bar(Step|Build)/", reps)
    print("### Bar step (CPU time per step) and build\n")
    rows = []
    for n in (30, 300, 3000):
        def t(kind, fem, uni):
            return time_text(r[f"BM_Bar{kind}/elements:{n}/fem:{fem}/unilateral:{uni}"]["cpu_ns"])
        rows.append([n, t("Step", 0, 0), t("Step", 0, 1), t("Step", 1, 0), t("Step", 1, 1), t("Build", 0, 0)])
    table(["elements", "xfem tied", "xfem unilateral", "fem tied", "fem unilateral", "build (xfem tied)"], rows)


def bar_events(bench, reps):
    r = run(bench, "BM_BarEventStep", reps)
    print("### Bar step with a located interface event\n")
    rows = []
    for n in (30, 300, 3000):
        plain, event = r[f"BM_BarEventStep/{n}/0"], r[f"BM_BarEventStep/{n}/1"]
        rows.append([n, time_text(plain["cpu_ns"]), time_text(event["cpu_ns"]), f"{event['factorisations']:.0f}"])
    table(["elements", "plain step", "step with a located event", "factorisations in it"], rows)


def coupled(bench, reps):
    r = run(bench, "BM_CoupledCase2", reps)
    print("### Case II coupled step\n")
    labels = {"fem_free_flight": "FE-DEM, free flight (t = 0.5 s)", "xfem_free_flight": "X-FE-DEM, free flight",
              "fem_resting": "FE-DEM, both particles resting on the rod (t = 8 s)", "xfem_resting": "X-FE-DEM, resting"}
    table(["Case II", "median per coupled step", "passes per step"],
          [[label, time_text(r[f"BM_CoupledCase2/{k}"]["cpu_ns"]), f"{r[f'BM_CoupledCase2/{k}']['passes_per_step']:.3g}"]
           for k, label in labels.items()])


def features(bench, reps):
    r = run(bench, "BM_Skip", reps)
    print("### Features: variant A (stage skipped) against B (present), ns per step and A/B\n")
    rows = []
    for name, b in sorted(r.items()):
        rows.append([name, time_text(b["A_ns"]), time_text(b["B_ns"]), f"{b['A_over_B']:.3f}"]
                    + ([time_text(b["C_ns"])] if "C_ns" in b else [""])
                    + ([f"{b['passes_free']:.3g} / {b['passes_resting']:.3g}"] if "passes_free" in b else [""]))
    table(["benchmark", "A", "B", "A/B", "C", "passes free / resting"], rows)


def energy_check(bench, reps):
    r = run(bench, "BM_BarStepEnergyCheck|BM_DemPacking/verlet(_energy_check_off|_energy_check_every_step)?/10000/",
            reps)
    print("### The energy balance check: off, every 16 steps (default), every step\n")
    rows = []
    for n in (300, 3000):
        rows.append([f"bar, {n} elements (X-FEM, tied)"]
                    + [time_text(r[f"BM_BarStepEnergyCheck/{n}/{k}"]["cpu_ns"]) for k in (0, 16, 1)])
    for workers in (1, 2):
        def per_step(variant):  # wall time of a step of the 10⁴ packing
            b = r[f"BM_DemPacking/{variant}/10000/{workers}/-1/real_time"]
            return time_text(b["per_particle_step"] * 1e9 * 10000)
        rows.append([f"packing, 10⁴ spheres, {'one worker' if workers == 1 else 'two workers'}",
                     per_step("verlet_energy_check_off"), per_step("verlet"),
                     per_step("verlet_energy_check_every_step")])
    table(["step", "off", "every 16 steps", "every step"], rows)


def workers(bench, reps):
    r = run(bench, "BM_DemPacking/(verlet|abm4)/", reps)
    print("### Two workers (wall time, ns per particle-step)\n")
    rows = []
    for variant in ("verlet", "abm4"):
        for n in (1000, 10000, 100000):
            one = r[f"BM_DemPacking/{variant}/{n}/1/-1/real_time"]["per_particle_step"] * 1e9
            two = r[f"BM_DemPacking/{variant}/{n}/2/-1/real_time"]["per_particle_step"] * 1e9
            rows.append([variant, f"{n:,}".replace(",", " "), f"{one:.1f}", f"{two:.1f}", f"{one / two:.2f}"])
    table(["integrator", "N", "1 worker", "2 workers", "speed-up"], rows)


def threshold(bench, reps):
    r = run(bench, "BM_DemPacking/threshold/", reps)
    sizes = (250, 500, 1000, 2000, 4000, 8000)
    print("### Where two workers start to pay (verlet, µs per step, wall time)\n")

    def row(workers, split):
        return [f"{r[f'BM_DemPacking/threshold/{n}/{workers}/{split}/real_time']['per_particle_step'] * 1e9 * n / 1e3:.3g}"
                for n in sizes]
    table(["N"] + [str(n) for n in sizes], [["1 worker, unsplit"] + row(1, 0), ["2 workers, split"] + row(2, 1)])


TABLES = {"drop": drop, "packing": packing, "bar": bar, "bar_events": bar_events, "coupled": coupled,
          "features": features, "energy_check": energy_check, "workers": workers, "threshold": threshold}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build/release")
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--tables", default=",".join(TABLES))
    args = parser.parse_args()
    bench = f"{args.build}/bench/xfdem_bench"
    for name in args.tables.split(","):
        if name not in TABLES:
            sys.exit(f"bench_tables: unknown table '{name}' (known: {', '.join(TABLES)})")
        TABLES[name](bench, args.repetitions)


if __name__ == "__main__":
    main()
