#!/bin/sh
# Build the hmat-oss side of the comparison (needs: apt-get install libhmat-oss-dev).
# Same flags as the project's extension (CMakeLists.txt): -O3 -march=native -fno-math-errno.
set -e
here=$(cd "$(dirname "$0")" && pwd)
src="$here/../../cpp/bemcontact"
out=${1:-/tmp/hmatoss/hmatoss_bench}
mkdir -p "$(dirname "$out")"
g++ -std=c++17 -O3 -march=native -fno-math-errno -fopenmp -Wall -Wextra \
    -I"$src" "$here/hmatoss_bench.cpp" "$src/operators.cpp" -lhmat -o "$out"
echo "built $out"
