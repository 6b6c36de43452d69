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
cmake --build "$work" -j"$(nproc)" >/dev/null
out=$("$work/consumer")
echo "$out"
grep -q "^evaluated volume 7\.8597" <<<"$out"
grep -q "^(0.5, 0.5, 0.5) inside$" <<<"$out"
grep -q "^(1.9, 1.9, 1.9) outside$" <<<"$out"
echo "consumer: OK"
