#!/usr/bin/env bash
# Lint of a change (docs/contributing.md "Style and lint"):
#   (a) no changed line of a C/C++ file is over 100 columns (characters, UTF-8);
#   (b) the changed lines of C/C++ files conform to the repository's .clang-format
#       (clang-format --dry-run -Werror --lines=...; skipped with a message when clang-format
#       is not installed);
#   (c) no file of the tree (C/C++, Markdown, CMake, Python, shell) refers to the project notes
#       kept outside the repository; docs/contributing.md alone may name them.
# "Changed" is relative to a base commit: $LINT_BASE if set, else `git merge-base HEAD
# origin/main` when origin/main exists, else HEAD~1. The working tree is compared with the base,
# so uncommitted edits count, and untracked C/C++ files are checked whole. Only changed lines are
# checked by (a) and (b), so lines a change does not touch are not reported; LINT_WHOLE_FILES=1
# checks the changed files whole. LINT_ALL=1 checks every tracked C/C++ file whole (what CI runs:
# the whole tree is formatted and within the limit).
# Prints one "file:line: message" per problem and exits 1 if there is any, else 0.
# Usage: scripts/lint.sh            LINT_BASE=main scripts/lint.sh
set -euo pipefail
cd "$(dirname "$0")/.."

limit=100
empty_tree=$(git hash-object -t tree /dev/null)
if [ -n "${LINT_BASE:-}" ]; then
  base=$(git rev-parse --verify "${LINT_BASE}^{commit}") || {
    echo "lint: LINT_BASE=$LINT_BASE is not a commit" >&2
    exit 2
  }
elif git rev-parse --verify -q origin/main >/dev/null; then
  base=$(git merge-base HEAD origin/main)
elif git rev-parse --verify -q HEAD~1 >/dev/null; then
  base=$(git rev-parse HEAD~1)
else
  base=$empty_tree
fi

status=0
cxx=('*.h' '*.hpp' '*.hh' '*.c' '*.cc' '*.cpp' '*.cxx')

# Changed C/C++ files (added, copied, modified, renamed), and untracked ones; with LINT_ALL=1
# every tracked one.
if [ "${LINT_ALL:-0}" = 1 ]; then
  mapfile -t changed < <(git ls-files -- "${cxx[@]}")
  LINT_WHOLE_FILES=1
else
  mapfile -t changed < <(git diff --name-only --diff-filter=ACMR "$base" -- "${cxx[@]}")
fi
mapfile -t untracked < <(git ls-files --others --exclude-standard -- "${cxx[@]}")

# "LINE COUNT" ranges of the lines `file` adds relative to the base (from the diff's hunk
# headers); a whole file when it is untracked or LINT_WHOLE_FILES=1.
added_ranges() {
  local file=$1 whole=$2
  if [ "$whole" = 1 ]; then
    local n
    n=$(awk 'END { print NR }' "$file")
    [ "$n" -gt 0 ] && echo "1 $n"
    return 0
  fi
  git diff -U0 --no-color "$base" -- "$file" |
    sed -n 's/^@@ -[0-9,]* +\([0-9]*\)\(,\([0-9]*\)\)\{0,1\} @@.*/\1 \3/p' |
    while read -r start count; do
      count=${count:-1}
      [ "$count" -gt 0 ] && echo "$start $count"
    done
  return 0
}

have_clang_format=0
if command -v clang-format >/dev/null 2>&1; then
  have_clang_format=1
else
  echo "lint: clang-format not installed: formatting check (b) skipped" >&2
fi

check_file() {
  local file=$1 whole=$2
  [ -f "$file" ] || return 0
  local ranges
  ranges=$(added_ranges "$file" "$whole")
  [ -n "$ranges" ] || return 0
  # (a) line length, in characters, on the added lines only.
  local awk_ranges
  awk_ranges=$(tr '\n' ' ' <<<"$ranges")
  if ! perl -CSD -Mutf8 -e '
      my ($file, $limit, @r) = @ARGV;
      my %want;
      while (@r) { my ($s, $c) = splice(@r, 0, 2); $want{$_} = 1 for $s .. $s + $c - 1; }
      open(my $fh, "<:encoding(UTF-8)", $file) or die "$file: $!\n";
      my $bad = 0;
      while (my $line = <$fh>) {
        chomp $line;
        next unless $want{$.};
        my $n = length($line);
        if ($n > $limit) { print "$file:$.: line is $n columns (limit $limit)\n"; $bad = 1; }
      }
      exit $bad;' "$file" "$limit" $awk_ranges; then
    status=1
  fi
  # (b) clang-format on the same lines.
  if [ "$have_clang_format" = 1 ]; then
    local args=() start count
    while read -r start count; do
      args+=("--lines=$start:$((start + count - 1))")
    done <<<"$ranges"
    if ! clang-format --style=file --dry-run -Werror "${args[@]}" "$file"; then
      status=1
    fi
  fi
}

for f in "${changed[@]}"; do check_file "$f" "${LINT_WHOLE_FILES:-0}"; done
for f in "${untracked[@]}"; do check_file "$f" 1; done

# (c) references to files outside the repository. The pattern is built from parts so that
# this script does not match itself.
notes='CONTRACT|DESIGN|STYLE'
pattern="(${notes})[.]md"
if git grep --untracked -n -E "$pattern" -- \
    "${cxx[@]}" '*.md' '*CMakeLists.txt' '*.cmake' '*.py' '*.sh' \
    ':!docs/contributing.md' | sed 's/$/  <- names a file outside the repository; cite docs\/ instead/'; then
  status=1
fi

if [ "$status" -ne 0 ]; then
  echo "lint: problems found (base $(git rev-parse --short "$base"))" >&2
else
  echo "lint: ok (base $(git rev-parse --short "$base"), ${#changed[@]} changed and ${#untracked[@]} untracked C/C++ files)"
fi
exit "$status"
