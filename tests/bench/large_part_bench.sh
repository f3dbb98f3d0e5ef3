#!/bin/sh
# The scale benchmark: one `curvedslicer layers` or `plan` run on the large
# thin-walled part that `large_part_bench` generates (600 x 400 x 300 mm open-top box, 8 mm walls),
# under /usr/bin/time -v, then a summary from report.json: grid, time and peak memory per stage,
# bytes per bounding-box cell, layers, triangles, points, and the load average before and after.
# One run per call (the process's peak resident set is the run's); see README.md, section
# "Large thin-walled part".
#
# Usage: tests/bench/large_part_bench.sh BUILD_DIR WORK_DIR layers|plan VOXEL_MM [CLI options...]
#   e.g. tests/bench/large_part_bench.sh build /tmp/large layers 1.0
#        tests/bench/large_part_bench.sh build /tmp/large layers 0.5 --memory-budget 24576
# Defaults: --layer-thickness 1.5, and for `plan` --bead-spacing 3.7; further options are appended.
set -eu
if [ $# -lt 4 ]; then
  sed -n '9,12p' "$0" >&2
  exit 2
fi
build=$1 work=$2 job=$3 voxel=$4
shift 4
case $job in
  layers) extra="" ;;
  plan) extra="--bead-spacing 3.7" ;;
  *) echo "large_part_bench.sh: job must be layers or plan: '$job'" >&2; exit 2 ;;
esac
mkdir -p "$work"
model=$work/large_box.stl
[ -f "$model" ] || "$build/tests/bench/large_part_bench" "$model"
out=$work/${job}_$voxel
rm -rf "$out"
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
start=$(date -u +%H:%M:%S)
set +e
# shellcheck disable=SC2086
/usr/bin/time -v -o "$out.time" nice -n 5 "$build/cpp/curvedslicer" "$job" "$model" \
  --layer-thickness 1.5 --voxel "$voxel" $extra -o "$out" -q "$@" 2> "$out.stderr"
code=$?
set -e
end=$(date -u +%H:%M:%S)
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
echo "$job L=$voxel $*: exit code $code, $(date -u +%F) $start-$end UTC," \
  "load average before $load_before, after $load_after"
if [ $code -ne 0 ]; then
  cat "$out.stderr"
  exit $code
fi
python3 - "$out/report.json" "$out.time" <<'EOF'
import json, re, sys
report = json.load(open(sys.argv[1]))
timed = open(sys.argv[2]).read()
rss_kib = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", timed).group(1))
wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", timed).group(1)
user = float(re.search(r"User time \(seconds\): (\S+)", timed).group(1))
system = float(re.search(r"System time \(seconds\): (\S+)", timed).group(1))
layer_report = report.get("layer_job", report)  # `plan` nests the layer job's report
grid = layer_report["grid"]
timing = layer_report["timing"]
cells = grid["cells"]
print(f"grid {' x '.join(str(d) for d in grid['dims'])} = {cells:,} cells at {grid['voxel_size_mm']} mm,"
      f" {grid['inside_voxels']:,} inside voxels")
peaks = timing["stage_peak_memory_bytes"]
for stage, seconds in timing["stage_seconds"].items():
    print(f"  {stage:14s} {seconds:9.2f} s   process peak after it {peaks[stage] / 1e9:6.2f} GB"
          f" = {peaks[stage] / cells:6.2f} B/cell")
layers = layer_report.get("layers", [])
triangles = sum(layer["triangles"] for layer in layers)
vertices = sum(layer["vertices"] for layer in layers)
outputs = layer_report["outputs"]
print(f"layers {outputs['layer_count']}, {triangles:,} triangles, {vertices:,} vertices,"
      f" {outputs['voxel_set_points']:,} eq. 13 points, {outputs['layer_batches']} batches")
peak = layer_report["peak_memory_bytes"]
print(f"layer job total {timing['total_seconds']:.1f} s; peak {peak / 1e9:.2f} GB ="
      f" {layer_report['peak_memory_bytes_per_cell']:.2f} B per bounding-box cell")
if "plan" in report:
    plan = report["plan"]
    print("plan:", json.dumps({k: v for k, v in plan.items() if not isinstance(v, (list, dict))}))
    for stage, seconds in plan.get("stage_times", {}).items():
        print(f"  plan {stage:24s} {seconds:9.2f} s")
print(f"/usr/bin/time: wall {wall}, user {user:.1f} s, system {system:.1f} s, maximum resident set"
      f" {rss_kib * 1024 / 1e9:.2f} GB = {rss_kib * 1024 / cells:.2f} B/cell")
EOF
