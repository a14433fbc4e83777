#!/usr/bin/env bash
# What self-contact costs. Part 1, where no pair comes close: the bundled S-start at 100
# elements (as bundled) and at 200, run by an OLD build (without self-contact) and this
# build, alternately K times in one window (old, new, old, new, ...); per pair the ratio of
# the simulation wall times (summary.json's wall_time_s), with the median and the range, and
# whether v_s/v_m is the same to the bit. Part 2, where the body flails and presses on
# itself: the phase map's cell W 127.4, G 100 (problems/phase_fine.toml's base) at 50 and 200
# elements, with self-contact on and off ([self_contact] enabled = false, where the
# body passes through itself), this build, one run each. Kept as a dated record
# docs/results/self-contact-cost/<date>.md.
#
#   lab/self_contact_cost/self_contact_cost.sh OLD_BINARY [K]     # K pairs (default 7)
#
# OLD_BINARY: a `slither` built from a commit before self-contact (e.g. 80c518e: `git worktree
# add /tmp/old 80c518e && CARGO_TARGET_DIR=/tmp/old-target cargo build --release
# --manifest-path /tmp/old/Cargo.toml`).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
if [ "${1:-}" != "--inner" ]; then
    [ $# -ge 1 ] || { echo "usage: lab/self_contact_cost/self_contact_cost.sh OLD_BINARY [K]" >&2; exit 2; }
    exec tools/record.sh self-contact-cost "$0" --inner "$1" "${2:-7}"
fi
old="$2"
k="$3"
[ -x "$old" ] || { echo "self_contact_cost.sh: $old is not an executable" >&2; exit 2; }
case "$k" in '' | *[!0-9]* | 0) echo "self_contact_cost.sh: K must be a positive whole number, got '$k'" >&2; exit 2 ;; esac
. tools/build.sh
use_slither
new="$SLITHER"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

cp problems/s_start.toml "$tmp/s_start_100.toml"
sed -e "s/^elements = .*/elements = 200/" problems/s_start.toml >"$tmp/s_start_200.toml"
for rep in $(seq 1 "$k"); do
    for n in 100 200; do
        "$old" run "$tmp/s_start_$n.toml" --out "$tmp/old-$n-$rep" --no-plots --quiet
        "$new" run "$tmp/s_start_$n.toml" --out "$tmp/new-$n-$rep" --no-plots --quiet
    done
done

for n in 50 200; do
    for on in true false; do
        d="$tmp/cell-$n-$on"
        mkdir -p "$d"
        sed -e "s/^elements = .*/elements = $n/" problems/phase_fine_base.toml >"$d/phase_fine_base.toml"
        printf '\n[self_contact]\nenabled = %s\n' "$on" >>"$d/phase_fine_base.toml"
        cp problems/phase_fine.toml "$d/phase_fine.toml"
        "$new" phase "$d/phase_fine.toml" --cell 127.42749857031336,100 --out "$d/out" >/dev/null
    done
done

python3 - "$tmp" "$k" <<'EOF'
import json, statistics, sys
tmp, k = sys.argv[1], int(sys.argv[2])
load = lambda p: json.load(open(p))
print(f"Part 1: bundled S-start, old build against this build, {k} alternating pairs; wall s of the time stepping")
for n in (100, 200):
    old = [load(f"{tmp}/old-{n}-{i}/summary.json") for i in range(1, k + 1)]
    new = [load(f"{tmp}/new-{n}-{i}/summary.json") for i in range(1, k + 1)]
    print()
    print(f"{n} elements")
    print()
    print("| pair | old | new | new / old |")
    print("|---|---|---|---|")
    ratios = []
    for i in range(k):
        a, b = old[i]["wall_time_s"], new[i]["wall_time_s"]
        ratios.append(b / a)
        print(f"| {i + 1} | {a:.3f} | {b:.3f} | {b / a:.3f} |")
    same = all(o["v_s_over_v_m"] == nw["v_s_over_v_m"] for o, nw in zip(old, new))
    sc = new[0]["self_contact"]
    print()
    print(f"median new / old {statistics.median(ratios):.3f} (range {min(ratios):.3f} to {max(ratios):.3f}); "
          f"v_s/v_m old {old[0]['v_s_over_v_m']!r}, new {new[0]['v_s_over_v_m']!r}, same to the bit: {same}; "
          f"closest pair {sc['closest_over_a']:.3f} a, steps with active pairs {sc['active_steps']}")
print()
print("Part 2: flailing cell W 127.4, G 100 (phase_fine_base.toml at dt 4e-3 s), this build, one run each")
print()
print("| elements | self-contact | wall s | Newton it. per step | halvings | conic fallbacks | closest over a | max pairs | regime | v_s/v_m |")
print("|---|---|---|---|---|---|---|---|---|---|")
for n in (50, 200):
    for on in ("true", "false"):
        s = load(f"{tmp}/cell-{n}-{on}/out/summary.json")
        st, sc = s["stats"], s["self_contact"]
        c = sc["closest_over_a"]
        print(f"| {n} | {'on' if on == 'true' else 'off'} | {s['wall_time_s']:.2f} | "
              f"{st['newton_iterations'] / max(st['steps'], 1):.2f} | {st['step_halvings']} | "
              f"{st['semismooth_fallbacks']} | {c if c is None else round(c, 4)} | {sc['max_pairs']} | "
              f"{s.get('regime')} | {s['v_s_over_v_m']:.4f} |")
EOF
