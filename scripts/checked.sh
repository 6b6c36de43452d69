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
# intercept_tls_get_addr=0: with it on, LeakSanitizer walks the dynamic TLS blocks it recorded
# through __tls_get_addr and, under Debian 12's glibc 2.36 with GCC 12's runtime, reads a garbage
# block once a dlopen'ed module with thread-locals (the OpenVDB plugin, cover_vdb.so) has run on
# TBB's threads: "Tracer caught signal 11" at exit, every run of `cover voxelize ... -o g.vdb`.
# Off, the blocks are ordinary heap allocations reachable from glibc's DTV: leaks are still
# found, and no false report appears (checked on the same command with use_tls=0, which reports
# the thread-local scratch buffers as leaks).
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:intercept_tls_get_addr=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# A failing test runs once more and fails the build only when it fails again, so that a one-off
# stall of the 2-core CI machine does not hide the suite's verdict; a sanitizer report is
# deterministic for the same input and fails both runs.
ctest --test-dir build-checked --output-on-failure -j"$(nproc)" --repeat until-pass:2
