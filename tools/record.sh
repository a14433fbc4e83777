#!/usr/bin/env bash
# Run a measuring command and keep its output as a dated record under docs/results/.
#
#   tools/record.sh NAME COMMAND [ARGS...]
#
# writes docs/results/NAME/<UTC date>.md (a suffix -2, -3, ... when that exists) holding the
# machine (uname -a, nproc, CPU model), the build (git commit, whether the work tree had
# changes, rustc version), the load average before and after (/proc/loadavg), the command, its
# exit code and wall time, and everything it printed. The command's output also goes to the
# terminal, and the record is copied to docs/results/NAME/latest.md, the one the guide cites
# (dated records stay as files). The exit code is the command's. Examples:
#
#   tools/record.sh tolerance-check cargo run --release --example tolerance_check
#   tools/record.sh bench-s-start cargo bench --bench s_start
#
# The guide cites the latest record of each kind; old records stay as files.
set -euo pipefail

if [ $# -lt 2 ]; then
    echo "usage: tools/record.sh NAME COMMAND [ARGS...]" >&2
    exit 2
fi
name="$1"
shift
case "$name" in
    *[!A-Za-z0-9_-]*) echo "record.sh: NAME may use only letters, digits, - and _" >&2; exit 2 ;;
esac

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="$repo/docs/results/$name"
mkdir -p "$dir"
day="$(date -u +%Y-%m-%d)"
file="$dir/$day.md"
n=2
while [ -e "$file" ]; do
    file="$dir/$day-$n.md"
    n=$((n + 1))
done

commit="$(git -C "$repo" rev-parse HEAD 2>/dev/null || echo unknown)"
if [ -n "$(git -C "$repo" status --porcelain --untracked-files=no 2>/dev/null)" ]; then
    tree="with uncommitted changes"
else
    tree="clean"
fi
cpu="$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//' || true)"
load_before="$(cat /proc/loadavg 2>/dev/null || echo unknown)"
started="$(date -u '+%Y-%m-%d %H:%M:%S UTC')"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT

t0="$(date +%s.%N)"
set +e
SLITHER_RECORDING=1 "$@" 2>&1 | tee "$log"
code="${PIPESTATUS[0]}"
set -e
t1="$(date +%s.%N)"
load_after="$(cat /proc/loadavg 2>/dev/null || echo unknown)"

{
    echo "# Record: $name"
    echo
    echo "Written by \`tools/record.sh\`; the numbers below are this run's, on this machine."
    echo
    echo "| | |"
    echo "|---|---|"
    echo "| started | $started |"
    echo "| command | \`$*\` |"
    echo "| exit code | $code |"
    echo "| wall time | $(awk "BEGIN { printf \"%.1f s\", $t1 - $t0 }") |"
    echo "| commit | \`$commit\` ($tree) |"
    echo "| rustc | $(rustc -V 2>/dev/null || echo unknown) |"
    echo "| machine | \`$(uname -a)\` |"
    echo "| cores | $(nproc) ($cpu) |"
    echo "| load average before | $load_before |"
    echo "| load average after | $load_after |"
    echo
    echo "## Output"
    echo
    echo '```text'
    cat "$log"
    echo '```'
} > "$file"
cp "$file" "$dir/latest.md"
echo "record: ${file#"$repo"/} (also $name/latest.md)" >&2
exit "$code"
