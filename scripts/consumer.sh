#!/usr/bin/env bash
# The package as an outside project sees it: installs the Release build in build/ into a
# temporary prefix, configures and builds examples/consumer against it with find_package(Cover)
# and no flags of its own, runs it and checks what it prints. Called by .ci/run after the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=$(mktemp -d)
work=$(mktemp -d)
trap 'rm -rf "$prefix" "$work"' EXIT
cmake --install build --prefix "$prefix" >/dev/null
cmake -S examples/consumer -B "$work" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
build_log=$(cmake --build "$work" -j"$(nproc)" --verbose)
# The consumer compiles at C++20 (the package's public compile feature) and inherits none of
# Cover's own flags (warnings, FP contraction, sanitizers).
compile=$(grep -E '(c\+\+|g\+\+|clang\+\+).* -c .*main\.cpp' <<<"$build_log")
grep -qE -- '-std=(c|gnu)\+\+(20|2a)' <<<"$compile" || { echo "consumer: not compiled as C++20: $compile"; exit 1; }
if grep -qE -- '-Wall|-Wextra|-ffp-contract|-fsanitize' <<<"$compile"; then
  echo "consumer: Cover's private flags leaked: $compile"; exit 1
fi
out=$("$work/consumer")
echo "$out"
grep -q "^evaluated volume 7\.8597" <<<"$out"
grep -q "^(0.5, 0.5, 0.5) inside$" <<<"$out"
grep -q "^(1.9, 1.9, 1.9) outside$" <<<"$out"
echo "consumer: OK"
