#!/usr/bin/env python3
"""Markdown summary of a semgraph_bench run (Google Benchmark JSON), python3 stdlib only.

    bench/summarize.py RESULTS.json [--memcheck MEMCHECK.json] [--icount ICOUNT.json]

Prints: the medians (and the fastest repetition, "min") of every query benchmark by depth, the
ratios compiled/raw quaternion chain, homogeneous/raw isometry chain, tf2 static/one-shot, the
tree builds (semgraph vs tf2, bytes and RSS per frame), the rejections by tree size, the latency
under a concurrent writer, the callgrind instruction counts when given, and the status of the
performance targets. Times are real time (wall clock), in ns unless marked.
"""
import argparse
import json
import sys

UNIT_NS = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}

QUERY_ROWS = [
    "compiled_pose_f2f", "compiled_pose_f2f_homogeneous", "compiled_pose_changes", "oneshot_by_names",
    "raw_eigen_quat_chain", "raw_eigen_iso_chain", "tf2_lookup_static", "tf2_lookup_dynamic",
]


def load(path):
    """{(family, arg): {aggregate: entry}} from a Google Benchmark JSON file."""
    data = json.load(open(path))
    out = {}
    for b in data.get("benchmarks", []):
        parts = b.get("run_name", b["name"]).split("/")
        family = parts[0]
        arg = int(parts[1]) if len(parts) > 1 and parts[1].isdigit() else None
        agg = b.get("aggregate_name", "single")
        if b.get("error_occurred"):
            agg = "error"
        out.setdefault((family, arg), {})[agg] = b
    return data.get("context", {}), out


def ns(entry):
    return entry["real_time"] * UNIT_NS[entry.get("time_unit", "ns")]


def get(res, family, arg, agg="median", key=None):
    e = res.get((family, arg), {}).get(agg) or res.get((family, arg), {}).get("single")
    if e is None:
        return None
    if key is None:
        return ns(e)
    return e.get(key)


def fmt(x, digits=3):
    if x is None:
        return "-"
    if abs(x) >= 1000:
        return f"{x:,.0f}"
    if abs(x) >= 100:
        return f"{x:.0f}"
    return f"{x:.{digits}g}"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(["---"] + ["---:"] * (len(header) - 1)) + "|"]
    for r in rows:
        lines.append("| " + " | ".join(r) + " |")
    return "\n".join(lines)


def args_of(res, family):
    return sorted(a for (f, a) in res if f == family and a is not None)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results")
    ap.add_argument("--memcheck")
    ap.add_argument("--icount")
    a = ap.parse_args()
    ctx, res = load(a.results)
    out = []
    p = out.append

    p(f"## semgraph_bench results ({ctx.get('date', '?')})\n")
    p(f"host: {ctx.get('host_name', '?')}, {ctx.get('num_cpus', '?')} CPUs @ {ctx.get('mhz_per_cpu', '?')} MHz, "
      f"load average at start {', '.join(f'{x:.2f}' for x in ctx.get('load_avg', []))}; "
      f"google-benchmark library_build_type: {ctx.get('library_build_type', '?')}. "
      f"semgraph commit {ctx.get('semgraph_commit', '?')}; {ctx.get('compiler', '')}; tf2: {ctx.get('semgraph_tf2', '?')}. "
      "Real time, median of the repetitions (\"min\": the fastest repetition).\n")

    depths = sorted({a for f in QUERY_ROWS for a in args_of(res, f)})
    for agg, title in [("median", "Queries, ns per query, median"), ("min", "Queries, ns per query, fastest repetition (min)")]:
        rows = []
        for f in QUERY_ROWS:
            if args_of(res, f):
                rows.append([f] + [fmt(get(res, f, d, agg)) for d in depths])
        if rows:
            p(f"### {title}\n")
            p(table(["benchmark \\ d"] + [str(d) for d in depths], rows) + "\n")

    ratio_defs = [
        ("compiled_pose_f2f / raw_eigen_quat_chain", "compiled_pose_f2f", "raw_eigen_quat_chain"),
        ("compiled_pose_f2f_homogeneous / raw_eigen_iso_chain", "compiled_pose_f2f_homogeneous", "raw_eigen_iso_chain"),
        ("compiled_pose_changes / compiled_pose_f2f", "compiled_pose_changes", "compiled_pose_f2f"),
        ("oneshot_by_names / compiled_pose_f2f", "oneshot_by_names", "compiled_pose_f2f"),
        ("tf2_lookup_static / oneshot_by_names", "tf2_lookup_static", "oneshot_by_names"),
        ("tf2_lookup_static / compiled_pose_f2f", "tf2_lookup_static", "compiled_pose_f2f"),
        ("tf2_lookup_dynamic / compiled_pose_f2f", "tf2_lookup_dynamic", "compiled_pose_f2f"),
    ]
    for agg in ["median", "min"]:
        rows = []
        for name, x, y in ratio_defs:
            vals = []
            for d in depths:
                u, v = get(res, x, d, agg), get(res, y, d, agg)
                vals.append(None if u is None or v is None else u / v)
            if any(v is not None for v in vals):
                rows.append([name] + ["-" if v is None else f"{v:.2f}" for v in vals])
        if rows:
            p(f"### Ratios of {'medians' if agg == 'median' else 'mins'}\n")
            p(table(["ratio \\ d"] + [str(d) for d in depths], rows) + "\n")

    ks = args_of(res, "compiled_twist")
    if ks:
        p("### compiled_twist (k twist edges), ns per query\n")
        p(table(["k", "median", "min"], [[str(k), fmt(get(res, "compiled_twist", k)), fmt(get(res, "compiled_twist", k, "min"))] for k in ks]) + "\n")

    sizes = sorted(set(args_of(res, "build_random_tree")) | set(args_of(res, "tf2_build_tree_static")))
    if sizes:
        rows = []
        for n in sizes:
            s_ms, t_ms = get(res, "build_random_tree", n), get(res, "tf2_build_tree_static", n)
            rows.append([f"{n:,}",
                         fmt(None if s_ms is None else s_ms / 1e6),
                         fmt(get(res, "build_random_tree", n, key="ns_per_add")),
                         fmt(get(res, "build_random_tree", n, key="bytes_per_frame")),
                         fmt(get(res, "build_random_tree", n, key="rss_B_per_frame")),
                         fmt(None if t_ms is None else t_ms / 1e6),
                         fmt(get(res, "tf2_build_tree_static", n, key="ns_per_add")),
                         fmt(get(res, "tf2_build_tree_static", n, key="rss_B_per_frame")),
                         "-" if s_ms is None or t_ms is None else f"{t_ms / s_ms:.2f}"])
        p("### Building a random tree of N frames (medians)\n")
        p(table(["N", "semgraph ms", "ns/add", "bytes/frame", "RSS B/frame", "tf2 ms", "tf2 ns/insert",
                 "tf2 RSS B/frame", "tf2 time / semgraph time"], rows) + "\n")
    if a.memcheck:
        _, mem = load(a.memcheck)
        rows = []
        for (f, n), aggs in sorted(mem.items(), key=lambda x: (x[0][0], x[0][1] or 0)):
            e = aggs.get("single") or next(iter(aggs.values()))
            rows.append([f, f"{n:,}", fmt(e.get("ns_per_add")), fmt(e.get("bytes_per_frame")), fmt(e.get("rss_B_per_frame"))])
        if rows:
            p("Fresh-process builds (one repetition each, memory check):\n")
            p(table(["benchmark", "N", "ns/add", "bytes/frame", "RSS B/frame"], rows) + "\n")

    rejects = [f for f in ["reject_P1", "reject_P3", "reject_W3"] if args_of(res, f)]
    if rejects:
        ns_ = sorted({n for f in rejects for n in args_of(res, f)})
        rows = []
        for f in rejects:
            vals = [get(res, f, n) for n in ns_]
            good = [v for v in vals if v is not None]
            spread = max(good) / min(good) if good else None
            rows.append([f] + [fmt(v) for v in vals] + ["-" if spread is None else f"{spread:.2f}"])
        p("### Rejections, ns per rejected add (median), by tree size N\n")
        p(table(["rule \\ N"] + [f"{n:,}" for n in ns_] + ["max/min"], rows) + "\n")

    cold = [(f, get(res, f, 200000), (res.get((f, 200000), {}).get("median") or {}).get("cpu_time"))
            for f in ["cold_oneshot_random_pairs", "cold_tf2_static_random_pairs"]]
    if all(v is not None for _, v, _ in cold):
        rows = [[f, fmt(v), fmt(c)] for f, v, c in cold]
        rows.append(["tf2 / semgraph", f"{cold[1][1] / cold[0][1]:.2f}",
                     "-" if cold[0][2] is None or cold[1][2] is None else f"{cold[1][2] / cold[0][2]:.2f}"])
        p("### Cold caches: one-shot query of random frame pairs in a 200,000-frame tree, ns (median)\n")
        p(table(["benchmark", "wall", "CPU"], rows) + "\n")

    lat_rows = []
    for f in ["latency_under_writer", "latency_under_writer_10khz", "latency_under_writer_1khz", "latency_no_writer"]:
        for d in [8, 64]:
            if (f, d) in res:
                keys = ["p50_ns", "p99_ns", "p99_9_ns", "max_ns", "p99_9_over_p50", "wall_ns_per_eval",
                        "cpu_ns_per_eval", "clock_ns_p50", "writes_per_s"]
                lat_rows.append([f, str(d)] + [fmt(get(res, f, d, key=k)) for k in keys])
    if lat_rows:
        p("### Compiled pose latency, ns per evaluation incl. two clock reads (median of repetitions)\n")
        p(table(["benchmark", "d", "p50", "p99", "p99.9", "max", "p99.9/p50", "wall/eval", "thread CPU/eval",
                 "clock p50", "writer SetPose/s"], lat_rows) + "\n")

    ir = {}
    if a.icount:
        ic = json.load(open(a.icount))
        for r in ic["results"]:
            ir[(r["kernel"], r["arg"])] = r["ir_per_op"]
        idepths = sorted({d for (k, d) in ir if k == "raw_eigen_quat_chain"})
        rows = [[k] + [fmt(ir.get((k, d))) for d in idepths] for k in QUERY_ROWS if any((k, d) in ir for d in idepths)]
        p("### Instructions per query (callgrind)\n")
        p(table(["kernel \\ d"] + [str(d) for d in idepths], rows) + "\n")
        others = sorted((k, d) for (k, d) in ir if k not in QUERY_ROWS)
        if others:
            p(table(["kernel", "arg (k or N)", "Ir per op"], [[k, f"{d:,}", fmt(ir[(k, d)])] for k, d in others]) + "\n")

    # ------------------------------------------------------------- targets
    status = []

    def target(name, ok, detail):
        status.append([name, "-" if ok is None else ("met" if ok else "MISSED"), detail])

    for d in [8, 64]:
        c, r = ir.get(("compiled_pose_f2f", d)), ir.get(("raw_eigen_quat_chain", d))
        target(f"compiled f2f <= 1.25x Ir of raw quat chain, d={d}", None if c is None or r is None else c / r <= 1.25,
               "-" if c is None or r is None else f"{c:,.0f} / {r:,.0f} Ir = {c / r:.2f}x")
        c, r = get(res, "compiled_pose_f2f", d), get(res, "raw_eigen_quat_chain", d)
        target(f"compiled f2f wall median <= 1.3x raw quat chain, d={d}", None if c is None or r is None else c / r <= 1.3,
               "-" if c is None or r is None else f"{c:.0f} / {r:.0f} ns = {c / r:.2f}x")
    o, t = ir.get(("oneshot_by_names", 8)), ir.get(("tf2_lookup_static", 8))
    target("one-shot by names >= 5x fewer Ir than tf2 static, d=8", None if o is None or t is None else t / o >= 5,
           "-" if o is None or t is None else f"tf2 {t:,.0f} / oneshot {o:,.0f} Ir = {t / o:.2f}x")
    for n in [100_000, 1_000_000]:
        s_, t_ = get(res, "build_random_tree", n), get(res, "tf2_build_tree_static", n)
        target(f"build random tree >= 3x faster than tf2, N={n:,}", None if s_ is None or t_ is None else t_ / s_ >= 3,
               "-" if s_ is None or t_ is None else f"tf2 {t_ / 1e6:.0f} ms / semgraph {s_ / 1e6:.0f} ms = {t_ / s_:.2f}x")
    for n in [100_000, 1_000_000]:
        b = get(res, "build_random_tree", n, key="bytes_per_frame")
        target(f"<= 160 bytes/frame, N={n:,}", None if b is None else b <= 160, "-" if b is None else f"{b:.0f} B/frame")
    for f in rejects:
        vals = [v for v in (get(res, f, n) for n in [1_000, 1_000_000]) if v is not None]
        irs = [ir.get((f, n)) for n in [1_000, 100_000]]
        detail = "-" if len(vals) < 2 else f"{vals[0]:.0f} -> {vals[1]:.0f} ns (x{vals[1] / vals[0]:.2f})"
        if None not in irs:
            detail += f"; Ir {irs[0]:,.0f} -> {irs[1]:,.0f} at 1e3 -> 1e5"
        ok = None if len(vals) < 2 else vals[1] / vals[0] <= 1.5
        target(f"{f} flat from 1e3 to 1e6 (wall x<=1.5)", ok, detail)
    p50, p999 = get(res, "latency_under_writer", 8, key="p50_ns"), get(res, "latency_under_writer", 8, key="p99_9_ns")
    target("p99.9 under a writer <= 3x median", None if p50 is None or p999 is None else p999 <= 3 * p50,
           "-" if p50 is None or p999 is None else f"p50 {p50:.0f} ns, p99.9 {p999:.0f} ns = {p999 / p50:.2f}x")
    p("### Targets\n")
    p(table(["target", "status", "measured"], status) + "\n")
    print("\n".join(out))


if __name__ == "__main__":
    sys.exit(main())
