#!/bin/sh
# Run the comparison: for each line "code size eps threads [extra args]" of a
# plan file (default: plan.txt beside this script), one process, one JSON line
# appended to RESULTS.  Cases are expected in /tmp/hmatoss/N<size> (export_case.py).
here=$(cd "$(dirname "$0")" && pwd)
plan=${1:-$here/plan.txt}
results=${2:-/tmp/hmatoss/results.jsonl}
py="$here/../../.venv/bin/python"
bin=/tmp/hmatoss/hmatoss_bench
grep -v '^#' "$plan" | while read -r code size eps threads extra; do
  [ -z "$code" ] && continue
  case_dir=/tmp/hmatoss/N$size
  echo "$(date +%T) $code N=$size eps=$eps threads=$threads $extra" >&2
  if [ "$code" = ours ]; then
    timeout 1800 "$py" "$here/ours_bench.py" "$case_dir" --eps "$eps" --threads "$threads" $extra >> "$results" \
      || echo "{\"code\": \"bemcontact\", \"nodes\": $size, \"eps\": $eps, \"error\": \"exit $?\"}" >> "$results"
  else
    OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1} timeout 1800 $bin "$case_dir" --eps "$eps" --threads "$threads" $extra >> "$results" \
      || echo "{\"code\": \"hmat-oss\", \"nodes\": $size, \"eps\": $eps, \"error\": \"exit $?\"}" >> "$results"
  fi
done
