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
# Its output against the CLI's exact answers for the same solids (cover volume --exact of the
# box minus the sphere: 7.1096605839902578; cover evaluate of the default scene's lower half:
# 3206 faces, volume 22.12645828755202, after the rounding repair collapsed 34 slivers of the
# turned torus lying across z = 0 within 4e-17).
scene=$(pwd)/models/default.json
out=$(cd "$work" && ./consumer "$scene")
echo "$out"
expected=$'volume 7.10966\ninside\noutside\nface\nvertex\n3206 faces, volume 22.1265\ntetrahedron 1\nown 6\ncall_once'
[ "$out" = "$expected" ] || { echo "consumer: unexpected output"; exit 1; }
[ -s "$work/half.off" ] || { echo "consumer: half.off not written"; exit 1; }
# Cover's headers are included as "cover/<module>/..." and ignore the consumer's own
# own/solid/types.h (its build above would fail otherwise): check the installed layout too.
[ -f "$prefix/include/cover/solid/types.h" ] || { echo "consumer: no include/cover/solid/types.h"; exit 1; }
if grep -rqE '#include "(solid|field|mesh|covering|render|voxel|octree|io|boolean|brep|model)/' "$prefix/include/cover"; then
  echo "consumer: an installed header includes another without the cover/ prefix"; exit 1
fi
# Every installed header includes only installed headers (the internals stay in the tree).
for h in $(cd "$prefix/include" && find cover -name '*.h'); do
  for inc in $(grep -oE '#include "cover/[^"]+"' "$prefix/include/$h" | sed -E 's/#include "(.*)"/\1/'); do
    [ -f "$prefix/include/$inc" ] || { echo "consumer: installed $h includes $inc, not installed"; exit 1; }
  done
done
echo "consumer: $(cd "$prefix/include" && find cover -name '*.h' | wc -l) installed headers"
# No Cover definition of a C library or C++ runtime symbol reaches the consumer: Cover's own
# pthread_once (solid/call_once.cpp) stays in Cover's programs, so the consumer's std::call_once
# binds to the C library's, and the consumer defines no pthread_, malloc/free or operator new.
defined=$(nm -C "$work/consumer" | awk '$2 ~ /^[TtWw]$/ {print $3}')
if grep -qE '^(pthread_|malloc$|free$|calloc$|realloc$|memcpy$|memset$|operator new|operator delete)' <<<"$defined"; then
  echo "consumer: defines a C library or C++ runtime symbol:"
  grep -E '^(pthread_|malloc$|free$|calloc$|realloc$|memcpy$|memset$|operator new|operator delete)' <<<"$defined"
  exit 1
fi
if objdump -d "$work/consumer" | grep -qE '<pthread_once>:'; then
  echo "consumer: objdump finds a pthread_once body in the consumer"; exit 1
fi
echo "consumer: OK"
