#!/usr/bin/env bash
# Instruction counts of the kinematics kernels (bench/kinematics_bench.cc) with callgrind.
#
#   bench/kinematics_icount.sh [BUILD_DIR]
#
# For each kernel and model (arm6, arm7): ITERS calls (default 1000) of icount_<kernel> under
#   valgrind --tool=callgrind --toggle-collect=icount_<kernel> semgraph_kinematics_bench --icount ...
# Ir per call = total Ir inside icount_<kernel> / ITERS. Prints a markdown table with the ratios
# against KDL and the targets (update + compiled EE pose >= 5x faster than kdl_fk; compiled
# Jacobian >= 3x faster than kdl_jacobian).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-$here/../build-bench}"
bin="$build/bench/semgraph_kinematics_bench"
iters="${ITERS:-1000}"
command -v valgrind >/dev/null || { echo "kinematics_icount.sh: valgrind is not installed" >&2; exit 1; }
[ -x "$bin" ] || { echo "kinematics_icount.sh: $bin not found" >&2; exit 1; }
work="$(mktemp -d -t semgraph-kin-icount.XXXXXX)"
declare -A ir
for model in arm6 arm7; do
  for kernel in sg_update_pose sg_update_pose_object sg_jacobian sg_update_jacobian kdl_fk kdl_jacobian; do
    out="$work/$kernel.$model.out"
    LD_BIND_NOW=1 valgrind --tool=callgrind --toggle-collect="icount_$kernel" --callgrind-out-file="$out" \
      "$bin" --icount "$kernel" "$model" "$iters" >"$work/$kernel.$model.log" 2>&1
    total="$(awk '/^totals:/ {print $2; exit} /^summary:/ {s=$2} END {if (s != "") print s}' "$out" | head -n1)"
    ir[$kernel.$model]=$((total / iters))
  done
done
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1fx", a / b }'; }
echo "| model | kernel | Ir / call | vs KDL | target |"
echo "|---|---|---:|---:|---|"
for model in arm6 arm7; do
  fk=${ir[kdl_fk.$model]}; jac=${ir[kdl_jacobian.$model]}
  echo "| $model | kdl_fk (ChainFkSolverPos_recursive) | $fk | 1.0x | |"
  echo "| $model | sg_update_pose (set all joints + compiled EE pose) | ${ir[sg_update_pose.$model]} | $(ratio "$fk" "${ir[sg_update_pose.$model]}") faster | >= 5x |"
  echo "| $model | sg_update_pose_object (set all joints + EE wrt a cup seen by a camera) | ${ir[sg_update_pose_object.$model]} | $(ratio "$fk" "${ir[sg_update_pose_object.$model]}") faster | |"
  echo "| $model | kdl_jacobian (ChainJntToJacSolver) | $jac | 1.0x | |"
  echo "| $model | sg_jacobian (compiled 6 x n Jacobian) | ${ir[sg_jacobian.$model]} | $(ratio "$jac" "${ir[sg_jacobian.$model]}") faster | >= 3x |"
  echo "| $model | sg_update_jacobian (set all joints + compiled Jacobian) | ${ir[sg_update_jacobian.$model]} | $(ratio "$jac" "${ir[sg_update_jacobian.$model]}") faster | |"
done
rm -rf "$work"
