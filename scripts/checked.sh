#!/usr/bin/env bash
# The checked build: the whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer
# (-O1, asserts on, every sanitizer report is fatal; -g1: line tables, enough for file:line in
# the reports' stacks, and a faster build than full debug info). Called by .ci/run after the
# README's test command; run it by hand the same way.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# COVER_BUILD_PYTHON=OFF: the sanitizer runtimes cannot be loaded into an uninstrumented python.
cmake -S . -B build-checked -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCOVER_SANITIZE=ON -DCOVER_BUILD_PYTHON=OFF \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1"
cmake --build build-checked -j"$(nproc)"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# A failing test runs once more: LeakSanitizer's tracer can itself crash at exit on a loaded
# machine ("Tracer caught signal 11" after a test that passed, seen once in the OpenVDB plugin's
# test); a real report, deterministic, fails both runs.
ctest --test-dir build-checked --output-on-failure -j"$(nproc)" --repeat until-pass:2
