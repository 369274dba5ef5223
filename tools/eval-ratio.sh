#!/bin/bash
# The evaluation pass with static shadows (DAG-MH by default) against the unshadowed pass (docs/culling.md's ratios), for one
# or more builds alternated round by round: per round and build, the minimum `evaluate` time of frames 1-9
# of `demo --size 640x360 --frames 10 --dynamic off`, unshadowed, one tap (--pcf 0) and 3x3 PCF (--pcf 1),
# and the two ratios. Fenced timing (the demo's default on CPU devices); alternate builds on a shared
# machine, since the load moves every figure. docs/culling.md, "Static lookups against the unshadowed pass".
set -euo pipefail
usage() {
    cat <<'USAGE'
usage: tools/eval-ratio.sh [--rounds N] [--bake FILE | --bake-each] [--by-level] [--out DIR] BIN [BIN ...]
       tools/eval-ratio.sh --summarize ROUNDS_CSV   (the median lines of an earlier run's rounds.csv)
  BIN          a manylights binary (copy old builds aside: binaries embed their shaders)
  --rounds N   rounds of alternation (default 3)
  --bake FILE  a bake of the night city, any method (default: DAG-MH made with the first BIN at 1024^2,
               all lights)
  --bake-each  each BIN bakes its own (builds whose bake formats differ)
  --by-level   each round also runs the two shadowed settings filtered by level (demo --by-level),
               reported as build "BIN by level" against the same round's unshadowed time
  --out DIR    where frames and the bakes go (default: a new temporary folder)
Prints one CSV line per round and build: round,bin,unshadowed_ms,one_tap_ms,pcf3x3_ms,one_tap_x,pcf3x3_x,
then per build a line with round "median": the median of each time over the rounds and the ratios of
those medians (the unshadowed pass's noise moves the per-round ratios most).
USAGE
}
# Per build in rounds.csv ($1): the median of each time over its rounds and the ratios of those medians.
# (Until 2026-12-03 evening the counter started unset, so round 1 went in as index "" and a 0 took
# its place in the sort; CliEvalRatioMedian checks the line against known figures.)
summarize() {
    awk -F, 'BEGIN { nb = 0 }
        NR > 1 && $1 != "median" {
            if (!($2 in n)) { n[$2] = 0; order[nb++] = $2 }
            k = n[$2]++; u[$2, k] = $3; t[$2, k] = $4; p[$2, k] = $5
        }
        function med(a, b, m,   i, j, x, v) {
            for (i = 0; i < m; i++) v[i] = a[b, i] + 0
            for (i = 1; i < m; i++) { x = v[i]; for (j = i - 1; j >= 0 && v[j] > x; j--) v[j + 1] = v[j]; v[j + 1] = x }
            return m % 2 ? v[(m - 1) / 2] : (v[m / 2 - 1] + v[m / 2]) / 2
        }
        END {
            for (i = 0; i < nb; i++) {
                b = order[i]; m = n[b]
                mu = med(u, b, m); mt = med(t, b, m); mp = med(p, b, m)
                printf "median,%s,%.1f,%.1f,%.1f,%.2f,%.2f\n", b, mu, mt, mp, mt / mu, mp / mu
            }
        }' "$1"
}
rounds=3 bake="" out="" each=0 level=0
bins=()
[ "${1:-}" = --summarize ] && { [ -f "${2:-}" ] || { echo "eval-ratio: --summarize needs a rounds.csv" >&2; exit 2; }; summarize "$2"; exit 0; }
while [ $# -gt 0 ]; do
    case "$1" in
    --help | -h) usage; exit 0 ;;
    --rounds) rounds="$2"; shift 2 ;;
    --bake) bake="$2"; shift 2 ;;
    --bake-each) each=1; shift ;;
    --by-level) level=1; shift ;;
    --out) out="$2"; shift 2 ;;
    -*) echo "eval-ratio: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) bins+=("$1"); shift ;;
    esac
done
[ ${#bins[@]} -gt 0 ] || { usage >&2; exit 2; }
for b in "${bins[@]}"; do [ -x "$b" ] || { echo "eval-ratio: $b is not an executable" >&2; exit 2; }; done
out="${out:-$(mktemp -d)}"
mkdir -p "$out"
[ "$each" = 0 ] || [ -z "$bake" ] || { echo "eval-ratio: --bake and --bake-each exclude each other" >&2; exit 2; }
bakes=()
for i in "${!bins[@]}"; do
    if [ -n "$bake" ]; then
        bakes+=("$bake")
    elif [ "$each" = 1 ] || [ "$i" = 0 ]; then
        f="$out/night-city-dagmh-1024-b$i.mlbk"
        echo "eval-ratio: baking $f with ${bins[$i]}" >&2
        "${bins[$i]}" bake --scene night-city --method dagmh --res 1024 --lights all --out "$f" >&2
        bakes+=("$f")
    else
        bakes+=("${bakes[0]}")
    fi
done
minEvaluate() { # frames.csv: frame,pass,gpu_ms
    awk -F, '$2 == "evaluate" && $1 >= 1 && $1 <= 9 { if (m == "" || $3 < m) m = $3 } END { printf "%.1f", m }' "$1"
}
echo "round,bin,unshadowed_ms,one_tap_ms,pcf3x3_ms,one_tap_x,pcf3x3_x" | tee "$out/rounds.csv"
for r in $(seq 1 "$rounds"); do
    for i in "${!bins[@]}"; do
        b="${bins[$i]}" d="$out/r${r}_b${i}"
        "$b" demo --size 640x360 --frames 10 --dynamic off --out "$d/none" >/dev/null
        "$b" demo --size 640x360 --frames 10 --dynamic off --bake "${bakes[$i]}" --pcf 0 --out "$d/tap" >/dev/null
        "$b" demo --size 640x360 --frames 10 --dynamic off --bake "${bakes[$i]}" --pcf 1 --out "$d/pcf" >/dev/null
        u=$(minEvaluate "$d/none/frames.csv") t=$(minEvaluate "$d/tap/frames.csv") p=$(minEvaluate "$d/pcf/frames.csv")
        awk -v r="$r" -v b="$b" -v u="$u" -v t="$t" -v p="$p" \
            'BEGIN { printf "%s,%s,%s,%s,%s,%.2f,%.2f\n", r, b, u, t, p, t / u, p / u }' | tee -a "$out/rounds.csv"
        [ "$level" = 1 ] || continue
        "$b" demo --size 640x360 --frames 10 --dynamic off --bake "${bakes[$i]}" --pcf 0 --by-level --out "$d/tapL" >/dev/null
        "$b" demo --size 640x360 --frames 10 --dynamic off --bake "${bakes[$i]}" --pcf 1 --by-level --out "$d/pcfL" >/dev/null
        t=$(minEvaluate "$d/tapL/frames.csv") p=$(minEvaluate "$d/pcfL/frames.csv")
        awk -v r="$r" -v b="$b by level" -v u="$u" -v t="$t" -v p="$p" \
            'BEGIN { printf "%s,%s,%s,%s,%s,%.2f,%.2f\n", r, b, u, t, p, t / u, p / u }' | tee -a "$out/rounds.csv"
    done
done
# Per build: medians over the rounds, and the ratios of the medians.
summarize "$out/rounds.csv"
