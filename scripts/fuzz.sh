#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) and runs each for SECONDS (default 600)
# with seed corpora from models/, the libcgal-demo meshes and assimp-testmodels. Findings
# (crash-*, leak-*, timeout-*, oom-*) land in build-fuzz/findings/TARGET/; turn each into a
# regression file under tests/data/fuzz/ and a test.
# Usage: scripts/fuzz.sh [SECONDS] [TARGET ...]   (targets: off obj stl ply scene)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(off obj stl ply scene)
scripts/setup.sh
command -v clang++ >/dev/null || { sudo=""; [ "$(id -u)" -ne 0 ] && sudo=sudo; $sudo apt-get install -y -qq clang libclang-rt-14-dev >/dev/null; }
# The libraries get coverage instrumentation too (fuzzer-no-link), or libFuzzer would be blind.
cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all" \
  -DCOVER_BUILD_FUZZ=ON -DCOVER_BUILD_TESTS=OFF >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target $(printf 'fuzz_%s ' "${targets[@]}")
cgal=build-fuzz/cgal-data/data/meshes
if [ ! -d "$cgal" ]; then
  mkdir -p build-fuzz/cgal-data && tar xzf /usr/share/doc/libcgal-dev/data.tar.gz -C build-fuzz/cgal-data data/meshes
fi
for t in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$t
  findings=build-fuzz/findings/$t
  mkdir -p "$corpus" "$findings"
  case $t in
    scene) cp models/*.json tests/data/fuzz/*.json "$corpus"/ ;;
    *) find models "$cgal" /usr/share/assimp/models tests/data/fuzz -iname "*.$t" -size -200k \
         -exec cp {} "$corpus"/ \; 2>/dev/null || true ;;
  esac
  echo "fuzz_$t: $seconds s" >&2
  build-fuzz/bin/fuzz_$t "$corpus" -max_total_time="$seconds" -rss_limit_mb=2048 \
    -malloc_limit_mb=1024 -timeout=10 -artifact_prefix="$findings/" -print_final_stats=1 2>&1 |
    grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|==|SUMMARY|INFO: -max_total_time)" || true
done
