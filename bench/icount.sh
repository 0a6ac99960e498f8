#!/usr/bin/env bash
# Instruction counts per query with callgrind (noise-free, unlike wall time on a shared VM).
#
#   bench/icount.sh [BUILD_DIR] [OUT_JSON]
#
# For each kernel of semgraph_icount at d = 8 and d = 64 (ITERS queries each, default 1000):
#   valgrind --tool=callgrind --toggle-collect=icount_<kernel> semgraph_icount <kernel> <d> ITERS
# and Ir per query = total Ir collected inside icount_<kernel> / ITERS (each kernel is one
# extern "C" noinline function doing one query; the count includes its call and return).
# Also, unless EXTRA=0: compiled_twist at k = 1, 2, 4; the rejections reject_P1/P3/W3 at
# N = 1e3, 1e4, 1e5 (flatness, noise-free); the random-tree build at N = 1e4 per inserted frame.
# Prints a markdown table (with the ratios compiled/raw and oneshot/tf2 static) and writes the
# numbers as JSON to OUT_JSON (default bench/results/icount-<UTC date>.json). Callgrind output
# files are kept in $ICOUNT_DIR (default: a temporary directory, printed) for callgrind_annotate.
# Paths in the JSON and the table are relative to the repository root, so that checked-in
# results do not carry the machine's directories (a directory outside the repository, such as
# the default temporary one, is recorded as null in the JSON).
# LD_BIND_NOW=1 so that lazy symbol binding is not counted in the first call.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
build="${1:-$root/build-bench}"
bin="$build/bench/semgraph_icount"
iters="${ITERS:-1000}"
depths="${DEPTHS:-8 64}"
extra="${EXTRA:-1}"
stamp="$(date -u +%Y-%m-%d)"
out_json="${2:-$here/results/icount-$stamp.json}"
work="${ICOUNT_DIR:-$(mktemp -d -t semgraph-icount.XXXXXX)}"
mkdir -p "$work" "$(dirname "$out_json")"

command -v valgrind >/dev/null || { echo "icount.sh: valgrind is not installed" >&2; exit 1; }
[ -x "$bin" ] || { echo "icount.sh: $bin not found (build first: bench/run.sh or cmake --build)" >&2; exit 1; }

kernels="compiled_pose_f2f compiled_pose_f2f_homogeneous compiled_pose_changes compiled_pose_cached_one compiled_pose_cached_all oneshot_by_names raw_eigen_quat_chain raw_eigen_iso_chain"
have_tf2=0
if "$bin" tf2_lookup_static 1 1 >/dev/null 2>&1; then
  have_tf2=1
  kernels="$kernels tf2_lookup_static tf2_lookup_dynamic"
fi

rows="$work/rows.tsv"   # kernel <tab> arg <tab> ops <tab> Ir
: > "$rows"

# run KERNEL ARG ITERS OPS_PER_ITER
run() {
  local kernel="$1" arg="$2" n="$3" ops="$4"
  local out="$work/callgrind.$kernel.$arg.out"
  if ! LD_BIND_NOW=1 valgrind --tool=callgrind --toggle-collect="icount_$kernel" \
        --callgrind-out-file="$out" "$bin" "$kernel" "$arg" "$n" >"$work/$kernel.$arg.log" 2>&1; then
    echo "icount.sh: $kernel $arg failed, see $work/$kernel.$arg.log" >&2
    exit 1
  fi
  local ir
  ir="$(awk '/^totals:/ {print $2; exit} /^summary:/ {s=$2} END {if (s != "") print s}' "$out" | head -n1)"
  printf '%s\t%s\t%s\t%s\n' "$kernel" "$arg" "$((n * ops))" "$ir" >> "$rows"
  printf 'icount: %-30s %8s  %12s Ir / %s ops\n' "$kernel" "$arg" "$ir" "$((n * ops))" >&2
}

for d in $depths; do
  for k in $kernels; do run "$k" "$d" "$iters" 1; done
done
if [ "$extra" != "0" ]; then
  for k in 1 2 4; do run compiled_twist "$k" "$iters" 1; done
  for n in 1000 10000 100000; do
    for k in reject_P1 reject_P3 reject_W3; do run "$k" "$n" "$iters" 1; done
  done
  run build_random_tree 10000 1 10000
  if [ "$have_tf2" = 1 ]; then run tf2_build_tree_static 10000 1 10000; fi
fi

python3 - "$rows" "$out_json" "$work" "$root" <<'EOF'
import json, os, sys
rows_path, out_json, work, root = sys.argv[1:5]

def relative(path):
    # Relative to the repository root when inside it; None (not recorded) otherwise.
    rel = os.path.relpath(os.path.realpath(path), os.path.realpath(root))
    return None if rel == ".." or rel.startswith(".." + os.sep) else rel
ir = {}
for line in open(rows_path):
    kernel, arg, ops, total = line.rstrip("\n").split("\t")
    ir[(kernel, int(arg))] = int(total) / int(ops)

def fmt(x):
    return "-" if x is None else (f"{x:,.0f}" if x >= 100 else f"{x:.2f}")

depths = sorted({a for (k, a) in ir if k == "raw_eigen_quat_chain"})
order = ["compiled_pose_f2f", "compiled_pose_f2f_homogeneous", "compiled_pose_changes", "oneshot_by_names",
         "raw_eigen_quat_chain", "raw_eigen_iso_chain", "tf2_lookup_static", "tf2_lookup_dynamic"]
print("### Instructions per query (callgrind Ir / query)\n")
print("| kernel \\ d | " + " | ".join(str(d) for d in depths) + " |")
print("|---|" + "---:|" * len(depths))
for k in order:
    if any((k, d) in ir for d in depths):
        print(f"| {k} | " + " | ".join(fmt(ir.get((k, d))) for d in depths) + " |")
def ratio(a, b, d):
    x, y = ir.get((a, d)), ir.get((b, d))
    return None if x is None or y is None else x / y
print()
print("| ratio \\ d | " + " | ".join(str(d) for d in depths) + " |")
print("|---|" + "---:|" * len(depths))
for name, a, b in [("compiled_pose_f2f / raw_eigen_quat_chain", "compiled_pose_f2f", "raw_eigen_quat_chain"),
                   ("compiled_pose_f2f_homogeneous / raw_eigen_iso_chain", "compiled_pose_f2f_homogeneous", "raw_eigen_iso_chain"),
                   ("compiled_pose_cached_one / raw_eigen_quat_chain", "compiled_pose_cached_one", "raw_eigen_quat_chain"),
                   ("compiled_pose_cached_all / raw_eigen_quat_chain", "compiled_pose_cached_all", "raw_eigen_quat_chain"),
                   ("oneshot_by_names / raw_eigen_quat_chain", "oneshot_by_names", "raw_eigen_quat_chain"),
                   ("tf2_lookup_static / oneshot_by_names", "tf2_lookup_static", "oneshot_by_names")]:
    vals = [ratio(a, b, d) for d in depths]
    if any(v is not None for v in vals):
        print(f"| {name} | " + " | ".join("-" if v is None else f"{v:.2f}" for v in vals) + " |")
extra = sorted((k, a) for (k, a) in ir if k not in order)
if extra:
    print("\n| kernel | arg (k or N) | Ir per op |")
    print("|---|---:|---:|")
    for k, a in extra:
        unit = " (per inserted frame)" if "build" in k else ""
        print(f"| {k}{unit} | {a:,} | {fmt(ir[(k, a)])} |")
json.dump({"unit": "Ir per query (callgrind, toggle-collect on the kernel)",
           "callgrind_dir": relative(work),
           "results": [{"kernel": k, "arg": a, "ir_per_op": v} for (k, a), v in sorted(ir.items())]},
          open(out_json, "w"), indent=1)
shown = lambda p: relative(p) or os.path.basename(p)
print(f"\n(JSON: {shown(out_json)}; callgrind files: {relative(work) or 'a temporary directory'})")
EOF
