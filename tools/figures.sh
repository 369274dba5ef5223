#!/usr/bin/env bash
# tools/figures.sh: regenerates every chart, image and table of README.md and docs/*.md by running the
# commands named next to them. Each step prints every command it runs ("+ ..."), writes its outputs and
# a log under out/figures/STEP/, copies its charts and images into docs/, and extracts the markdown
# tables the commands print into out/figures/STEP/tables.md (paste them into the docs by hand).
# The commands are the documented ones with their --out folder moved under out/figures/.
set -euo pipefail
cd "$(dirname "$0")/.."

BUILD=build
OUT=out/figures
SELECT=""
KIND=""
LIST=0
DRY=0
COPY=1
SLOW=0

usage() {
    cat <<'EOF'
Usage: tools/figures.sh [options]

Regenerates the charts, images and tables of README.md and docs/*.md by running the commands that
made them. Outputs go to out/figures/STEP/ (log.txt: the full output; tables.md: the markdown
tables the commands printed; the commands' CSV files); charts and images are copied into docs/.
The markdown files are not rewritten: paste from tables.md.

Options:
  --list           list the steps (name, kinds, the doc that holds the figure, what it makes) and exit
  --only A,B,...   run only these steps (any step, slow ones included)
  --charts         run the steps that make charts (the speed-accuracy PNGs)
  --images         run the steps that make images (demo frames, VSM views, failure cases)
  --tables         run the steps that make tables
  --slow           with no selection: also run the steps marked slow (fuzzing, sanitizers, 4K verify)
  --build DIR      the build folder holding manylights and the test binaries (default: build)
  --out DIR        where the outputs go (default: out/figures)
  --no-copy        do not copy charts and images into docs/
  --dry-run        print the commands without running them
  -h, --help       this text

Environment: SM_MAX (default 1024): the largest resolution at which bench static runs the plain map
(sm), which lavapipe's 128 MiB storage buffer range refuses for 8 lights from 2048^2 on; the other
methods run apart at every resolution. FZK_ONE_RUN=1: the fzk-haus benchmark as one command (on a
device whose range holds its bakes).

With no selection every step not marked slow runs, in --list order. Build first:
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build -j2
Absolute times in the figures depend on the machine and on what else runs on it: compare within one run.
EOF
}

# ---- step registry: name | kinds | doc | slow | description ---------------------------------------
STEPS=()
step() { STEPS+=("$1|$2|$3|$4|$5"); }
step demo            image        README.md                 -    "night city frame 0 with DAG-MH static shadows (tools/demo.sh) -> docs/night-city.png"
step closeup         image        README.md                 -    "lamp close-up, 1280x720 -> docs/night-city-closeup.png"
step view-lights     image        docs/culling.md           -    "light complexity views -> docs/night-city-lights.png, docs/night-city-lights-reaching.png"
step culling         table        docs/culling.md           -    "bench culling 256/1024/4096 lights, every mode"
step camera          table        docs/integration.md       -    "reversed-Z receiver error (gpu_tests GpuCamera*)"
step bench-static    chart,table  docs/static-shadows.md    -    "bench static 1K-4K, exact receivers -> docs/accuracy_vs_bytes.png, docs/accuracy_vs_time.png"
step static-closeup  table        docs/static-shadows.md    -    "bench static at the lamp close-up, 1K and 4K"
step static-fzk      chart,table  docs/static-shadows.md    -    "bench static on fzk-haus.glb 1K-8K -> docs/fzk_accuracy_vs_bytes.png"
step verify          table        docs/static-shadows.md    slow "bake + verify every method at 4096^2, 8 lights (every texel/voxel)"
step bake-parallel   table        docs/static-shadows.md    -    "sharded bake, 1 and 2 processes, against a plain bake"
step accuracy-city   table        docs/accuracy.md          -    "section 1: G-buffer against exact receivers, 512-4096"
step accuracy-closeup table       docs/accuracy.md          -    "section 2: cause breakdown at the close-up, 256-4096"
step accuracy-lookup chart,table  docs/accuracy.md          -    "section 3: isolated lookup cost -> docs/accuracy_vs_lookup.png"
step accuracy-atlas  table        docs/accuracy.md          -    "section 4: plain maps at the atlas sides of equal memory"
step directional     table        docs/accuracy.md          -    "section 5: directional bakes + verify, and through the module"
step failures        image,table  docs/accuracy.md          -    "section 6: failure suite -> docs/failures/*.png"
step flicker         table        docs/accuracy.md          -    "section 7: flicker of the static methods (camera path, moving lights, both)"
step flicker-vsm     table        docs/accuracy.md          -    "section 7: VSM flicker against plain maps"
step vsm-texels      table        docs/accuracy.md          -    "section 7: texels per pixel 1, 2, 4 (flicker and pages; the stability target's table)"
step need            table        docs/accuracy.md          -    "section 8: resolution from need (whole city bakes, bench static --need)"
step vsm-rays        table        docs/accuracy.md          -    "section 9: VSM one-tap answers against rays, night city and indoor, texels per pixel 0.5-4"
step vsm-drive       image        docs/virtual-shadow-maps.md -  "drive path frame 39 and its page view -> docs/vsm-drive.png, docs/vsm-drive-pages.png"
step vsm             table        docs/virtual-shadow-maps.md -  "bench vsm (no bake, bake, 128^2 pages), memory from demo stats, check vsm"
step vsm-meshlets    table        docs/vsm-page-draws.md    -    "mesh against vertex page draws, night city and fzk-haus, two runs each"
step vsm-pageclip    table        docs/vsm-page-draws.md    -    "page draws clipped to dirty pages against whole-mip draws, night city moon and indoor"
step fuzz            table        docs/reliability.md       slow "tools/fuzz.sh 660 (bake files and glTF)"
step sanitize        table        docs/reliability.md       slow "tools/sanitize.sh -j2 (ASan + UBSan build in build-asan/, whole ctest)"

field() { local IFS='|'; read -r -a f <<<"$1"; echo "${f[$2]}"; }

# ---- helpers ---------------------------------------------------------------------------------------
ML=""
LOG=/dev/null
D=""            # the current step's output folder

say() { echo "$*" | tee -a "$LOG"; }
# shown ARGS...: the arguments as a shell would take them back (quotes where needed).
shown() {
    local a out=""
    for a in "$@"; do
        if [[ "$a" =~ ^[A-Za-z0-9_./,:=+@%-]+$ ]]; then out+="$a "; else out+="\"$a\" "; fi
    done
    echo "${out% }"
}
# run CMD...: print it, run it niced, its output to the terminal and the step's log.
run() {
    say "+ $(shown "$@")"
    [ "$DRY" = 1 ] && return 0
    nice "$@" 2>&1 | tee -a "$LOG"
}
# runenv VAR=VALUE CMD...: the same with an environment variable.
runenv() {
    say "+ $(shown "$@")"
    [ "$DRY" = 1 ] && return 0
    env "$1" nice "${@:2}" 2>&1 | tee -a "$LOG"
}
copy() {
    [ "$COPY" = 1 ] || { say "(not copied: $1 -> $2)"; return 0; }
    say "copy $1 -> $2"
    [ "$DRY" = 1 ] && return 0
    mkdir -p "$(dirname "$2")"
    cp "$1" "$2"
}
# bake_once FILE ARGS...: bake FILE unless it is already a valid bake file (shared between steps).
bake_once() {
    local file=$1; shift
    if [ "$DRY" = 0 ] && "$ML" inspect "$file" >/dev/null 2>&1; then
        say "(reusing $file)"
        return 0
    fi
    [ "$DRY" = 1 ] || mkdir -p "$(dirname "$file")"
    run "$ML" bake "$@" --out "$file"
}
CITY1024() { echo "$OUT/bakes/night-city-dagmh-1024.mlbk"; }
CITY512() { echo "$OUT/bakes/city-dagmh-512.mlbk"; }
CLOSEUP=" -121,7,1,-129.8,0,-5.4"
FZK=../shared/scenes/fzk-haus.glb

# ---- steps -----------------------------------------------------------------------------------------
step_demo() {
    bake_once "$(CITY1024)" --scene night-city --method dagmh --res 1024 --lights all
    run "$ML" demo --scene night-city --frames 3 --bake "$(CITY1024)" --pcf 1 --out "$D/demo"
    copy "$D/demo/frame_0000.png" docs/night-city.png
}
step_closeup() {
    bake_once "$(CITY1024)" --scene night-city --method dagmh --res 1024 --lights all
    run "$ML" demo --bake "$(CITY1024)" --pcf 1 --frames 1 --size 1280x720 --camera "$CLOSEUP" --out "$D/closeup"
    copy "$D/closeup/frame_0000.png" docs/night-city-closeup.png
}
step_view-lights() {
    run "$ML" demo --view lights --frames 1 --size 640x360 --out "$D/view-lights"
    run "$ML" demo --view lights-reaching --frames 1 --size 640x360 --out "$D/view-reaching"
    copy "$D/view-lights/frame_0000.png" docs/night-city-lights.png
    copy "$D/view-reaching/frame_0000.png" docs/night-city-lights-reaching.png
}
step_culling() {
    run "$ML" bench culling --size 640x360 --lights 256,1024,4096 --frames 3 --csv "$D/bench_culling.csv"
}
step_camera() {
    run "$BUILD/gpu_tests" --gtest_filter='GpuCamera*'
}
# bench_static OUT ARGS...: a documented `bench static` command (ARGS hold --res, not --methods).
# The plain map (sm) of 8 lights takes 128 MiB at 2048^2, which setStaticShadow refuses on a device
# whose storage buffer range is 128 MiB (lavapipe), and bench static stops at the first refusal. So
# this runs the compressed methods at every resolution (OUT: tables, CSV, charts) and sm apart at the
# resolutions up to SM_MAX (OUT/sm). On a device with a larger range: SM_MAX=16384.
SM_MAX=${SM_MAX:-1024}
bench_static() {
    local out=$1; shift
    local args=("$@") smargs=() smres="" i
    for ((i = 0; i < ${#args[@]}; i++)); do
        smargs+=("${args[i]}")
        if [ "${args[i]}" = --res ]; then
            smres=$(echo "${args[i + 1]}" | tr , '\n' | awk -v m="$SM_MAX" '$1 <= m' | paste -sd, -)
            smargs+=("$smres")
            i=$((i + 1))
        fi
    done
    run "$ML" bench static --methods mh,mmh,dagmh,cpvs "${args[@]}" --out "$out"
    if [ -n "$smres" ]; then run "$ML" bench static --methods sm "${smargs[@]}" --out "$out/sm"; fi
}
step_bench-static() {
    bench_static "$D" --res 1024,2048,4096 --lights 8 --size 640x360 --frames 3 --lookup-pcf none
    copy "$D/accuracy_vs_bytes.png" docs/accuracy_vs_bytes.png
    copy "$D/accuracy_vs_time.png" docs/accuracy_vs_time.png
}
step_static-closeup() {
    bench_static "$D" --res 1024,4096 --lights 8 --frames 5 --camera "$CLOSEUP"
}
# fzk-haus compresses far less: with a 128 MiB storage buffer range (lavapipe) the 8 lights' MH words
# pass it at 4096^2 and DAG-MH's at 8192^2 (MH and MMH cannot encode 8192^2 at all: 24-bit offsets).
# So the documented command (FZK_ONE_RUN=1 runs it as it is) is split into runs that fit; the chart
# comes from the first.
step_static-fzk() {
    if [ "${FZK_ONE_RUN:-0}" = 1 ]; then
        run "$ML" bench static --scene "$FZK" --res 1024,2048,4096,8192 --lights 8 --frames 3 --out "$D"
    else
        run "$ML" bench static --methods mmh,dagmh,cpvs --scene "$FZK" --res 1024,2048,4096 --lights 8 --frames 3 --out "$D"
        run "$ML" bench static --methods mh --scene "$FZK" --res 1024,2048 --lights 8 --frames 3 --out "$D/mh"
        run "$ML" bench static --methods sm --scene "$FZK" --res 1024 --lights 8 --frames 3 --out "$D/sm"
        run "$ML" bench static --methods cpvs --scene "$FZK" --res 8192 --lights 8 --frames 3 --out "$D/cpvs8192"
    fi
    copy "$D/accuracy_vs_bytes.png" docs/fzk_accuracy_vs_bytes.png
}
step_verify() {
    local m
    for m in sm mh mmh dagmh cpvs; do
        run "$ML" bake --method $m --res 4096 --lights 0-7 --quiet --out "$D/$m.mlbk"
        run "$ML" verify "$D/$m.mlbk"
        run "$ML" inspect "$D/$m.mlbk" --json
        [ "$DRY" = 1 ] || rm -f "$D/$m.mlbk"
    done
}
step_bake-parallel() {
    local j
    for j in 1 2; do
        say "+ time tools/bake-parallel.sh --jobs $j ..."
        [ "$DRY" = 1 ] || { /usr/bin/time -f "jobs $j: %e s" nice tools/bake-parallel.sh --jobs $j --method dagmh \
            --res 2048 --lights 0-15 --quiet --out "$D/par$j.mlbk" 2>&1 | tee -a "$LOG"; }
    done
    run "$ML" bake --method dagmh --res 2048 --lights 0-15 --quiet --out "$D/plain.mlbk"
    run cmp "$D/par1.mlbk" "$D/plain.mlbk"
    run cmp "$D/par2.mlbk" "$D/plain.mlbk"
}
step_accuracy-city() {
    bench_static "$D/gbuffer" --res 512,1024,2048,4096 --frames 1 --lookup-pcf none --receivers gbuffer
    bench_static "$D/exact" --res 512,1024,2048,4096 --frames 1 --lookup-pcf none
}
step_accuracy-closeup() {
    bench_static "$D" --res 256,512,1024,2048,4096 --lights 8 --size 1280x720 --frames 3 --camera "$CLOSEUP" --lookup-pcf none
}
step_accuracy-lookup() {
    bench_static "$D" --res 1024,4096 --lights 8 --size 1280x720 --frames 1 --camera "$CLOSEUP"
    copy "$D/accuracy_vs_lookup.png" docs/accuracy_vs_lookup.png
}
step_accuracy-atlas() {
    run "$ML" bench static --methods sm --res 127,146,165,173,212,223,265,294,311,372,491,538 --lights 8 --size 1280x720 --frames 1 --camera "$CLOSEUP" --lookup-pcf none --out "$D"
}
step_directional() {
    local m
    for m in sm mh mmh dagmh cpvs; do
        run "$ML" bake --method $m --res 256 --lights 0 --scene-lights 16 --light-dir 0.3,-1,0.2 --out "$D/moon_$m.mlbk" --quiet
        run "$ML" verify "$D/moon_$m.mlbk" --quiet
        run "$ML" inspect "$D/moon_$m.mlbk" --json
    done
    run "$BUILD/failure_tests" --gtest_filter='*Directional*'
}
step_failures() {
    [ "$DRY" = 1 ] || mkdir -p "$D/images"
    runenv ML_FAILURE_IMAGES="$D/images" "$BUILD/failure_tests"
    local f
    if [ "$DRY" = 0 ]; then
        for f in "$D"/images/*.png; do copy "$f" "docs/failures/$(basename "$f")"; done
    else
        copy "$D/images/*.png" docs/failures/
    fi
}
step_flicker() {
    run "$ML" bench flicker --res 64,256,1024 --frames 16 --camera "$CLOSEUP" --out "$D/camera"
    run "$ML" bench flicker --res 64,256,1024 --frames 16 --camera "$CLOSEUP" --camera-end "$CLOSEUP" --light-move 0.1 --light-turn 0.5 --out "$D/lights"
    run "$ML" bench flicker --res 64,256,1024 --frames 16 --camera "$CLOSEUP" --light-move 0.1 --light-turn 0.5 --out "$D/moving"
}
step_flicker-vsm() {
    run "$ML" bench flicker --vsm --frames 16 --size 320x180 --pcf 0,2 --vsm-res 1024 --compare-res 1024 --out "$D/vsm_1024"
    run "$ML" bench flicker --vsm --frames 16 --size 320x180 --pcf 0,2 --vsm-res 4096 --compare-res 128 --out "$D/vsm_4096"
    run "$ML" bench flicker --vsm --frames 16 --size 640x360 --pcf 0,2 --vsm-res 4096 --compare-res 1024 --out "$D/vsm_640"
}
step_vsm-texels() {
    local t
    for t in 1 2 4; do
        run "$ML" bench flicker --vsm --frames 16 --size 320x180 --pcf 0,2 --vsm-res 4096 --vsm-texels $t --out "$D/flicker_texels_$t"
        run "$ML" bench vsm --kinds static-spot,moving-spot --vsm-raster vertex --frames 8 --size 320x180 --vsm-texels $t --out "$D/bench_vsm_texels_$t"
    done
    # The stability target's table: one tap (the module's default filter), pages from the same run.
    for t in 1/64 2/64 4/64 2/32 4/32; do
        run "$ML" bench flicker --vsm --frames 16 --size 320x180 --pcf 0 --vsm-res 4096 --compare-res 1024 --vsm-texels "${t%/*}" --vsm-page "${t#*/}" --out "$D/flicker_stable_${t%/*}_${t#*/}"
    done
    for t in 2 0.5 0.25 0; do
        run "$ML" bench flicker --vsm --frames 16 --size 320x180 --pcf 0 --vsm-res 4096 --compare-res 1024 --lamp-bias $t,0.5 --out "$D/flicker_bias_$t"
    done
    for t in 1 2 4; do
        run "$ML" bench flicker --vsm --frames 16 --size 320x180 --pcf 0,1 --vsm-res 4096 --compare-res 1024 --vsm-texels $t --bilinear --out "$D/flicker_bilinear_$t"
        run "$ML" bench flicker --vsm --frames 16 --size 320x180 --pcf 0,1 --vsm-res 4096 --compare-res 1024 --vsm-texels $t --lamp-bias 0.5,0.5 --bilinear --out "$D/flicker_both_$t"
    done
    # Per light: the static lights' LightDesc::shadowTexelScale, every other light at 1.
    for t in 2 4; do
        run "$ML" bench flicker --vsm --frames 16 --size 320x180 --pcf 0 --vsm-res 4096 --compare-res 1024 --lamp-texels $t --out "$D/flicker_lamps_$t"
    done
}
step_vsm-rays() {
    run "$ML" bench vsm-rays --scene night-city --frames 3 --size 320x180 --out "$D/city"
    run "$ML" bench vsm-rays --scene indoor --path static --frames 3 --size 320x180 --out "$D/indoor"
    run "$ML" bench vsm-rays --scene night-city --frames 3 --size 320x180 --texels 2 --vsm-pool 48 --compare-res 0 --out "$D/city_pool48"
}
step_need() {
    local r
    for r in 1024 2048; do
        run "$ML" bake --method dagmh --res $r --lights all --out "$D/fixed_$r.mlbk" --quiet
        run "$ML" bake --method dagmh --res $r --lights all --need path:drive --out "$D/need_$r.mlbk" --quiet
        run "$ML" inspect "$D/fixed_$r.mlbk" --json
        run "$ML" inspect "$D/need_$r.mlbk"
        run "$ML" verify "$D/need_$r.mlbk"
    done
    run "$ML" bench static --need path:drive --res 512,1024,2048,4096 --methods dagmh,cpvs --views 8 --size 1280x720 --out "$D/bench"
}
step_vsm-drive() {
    bake_once "$(CITY512)" --method dagmh --res 512 --lights all
    run "$ML" demo --bake "$(CITY512)" --frames 40 --size 640x360 --pcf 1 --path drive --out "$D/drive_img"
    run "$ML" demo --bake "$(CITY512)" --frames 40 --size 640x360 --pcf 1 --path drive --view vsm --out "$D/drive_pages"
    copy "$D/drive_img/frame_0039.png" docs/vsm-drive.png
    copy "$D/drive_pages/frame_0039.png" docs/vsm-drive-pages.png
}
step_vsm() {
    bake_once "$(CITY512)" --method dagmh --res 512 --lights all
    run "$ML" bench vsm --frames 10 --size 640x360 --kinds static-spot --vsm-raster vertex --out "$D/bench_vsm_nobake"
    run "$ML" bench vsm --bake "$(CITY512)" --frames 10 --size 640x360 --out "$D/bench_vsm_64"
    run "$ML" bench vsm --bake "$(CITY512)" --frames 10 --size 640x360 --vsm-page 128 --out "$D/bench_vsm_128"
    run "$ML" demo --bake "$(CITY512)" --path drive --frames 30 --size 640x360 --out "$D/drive"
    run "$ML" demo --path drive --frames 30 --size 640x360 --out "$D/drive_nobake"
    say "stats.json (vsm) of $D/drive and $D/drive_nobake:"
    [ "$DRY" = 1 ] || grep -A12 '"vsm"' "$D/drive/stats.json" "$D/drive_nobake/stats.json" | tee -a "$LOG" || true
    run "$ML" check vsm --frames 10
    run "$ML" check vsm --frames 10 --vsm-raster mesh
}
step_vsm-meshlets() {
    local i
    for i in 1 2; do
        run "$ML" bench vsm --frames 10 --kinds static-spot,moving-spot,directional --out "$D/city_$i"
        run "$ML" bench vsm --scene "$FZK" --path orbit --frames 4 --size 320x180 --kinds static-spot --out "$D/fzk_$i"
    done
}
step_vsm-pageclip() {
    local m
    for m in on off; do
        run "$ML" bench vsm --kinds directional --frames 4 --vsm-raster both --vsm-page-clip $m --out "$D/city_clip_$m"
        run "$ML" bench vsm --scene indoor --frames 4 --vsm-raster both --vsm-page-clip $m --out "$D/indoor_clip_$m"
    done
}
step_fuzz() {
    run tools/fuzz.sh 660
}
step_sanitize() {
    run tools/sanitize.sh -j2
}

# ---- main (one function, so that bash has read all of it before it runs: the file may change meanwhile)
main() {
    # ---- arguments -------------------------------------------------------------------------------------
    while [ $# -gt 0 ]; do
        case "$1" in
            -h|--help) usage; exit 0 ;;
            --list) LIST=1 ;;
            --only) [ $# -ge 2 ] || { echo "figures.sh: --only needs step names (--list shows them)" >&2; exit 2; }
                    SELECT="$SELECT,$2"; shift ;;
            --only=*) SELECT="$SELECT,${1#--only=}" ;;
            --charts) KIND="$KIND,chart" ;;
            --images) KIND="$KIND,image" ;;
            --tables) KIND="$KIND,table" ;;
            --slow) SLOW=1 ;;
            --build) [ $# -ge 2 ] || { echo "figures.sh: --build needs a folder" >&2; exit 2; }
                     BUILD=$2; shift ;;
            --out) [ $# -ge 2 ] || { echo "figures.sh: --out needs a folder" >&2; exit 2; }
                   OUT=$2; shift ;;
            --no-copy) COPY=0 ;;
            --dry-run) DRY=1 ;;
            *) echo "figures.sh: unknown option '$1' (--help)" >&2; exit 2 ;;
        esac
        shift
    done

    if [ "$LIST" = 1 ]; then
        printf '%-17s %-12s %-28s %-5s %s\n' STEP KINDS DOC SLOW MAKES
        for s in "${STEPS[@]}"; do
            printf '%-17s %-12s %-28s %-5s %s\n' "$(field "$s" 0)" "$(field "$s" 1)" "$(field "$s" 2)" \
                "$(field "$s" 3)" "$(field "$s" 4)"
        done
        exit 0
    fi

    # Which steps run.
    chosen=()
    IFS=',' read -r -a wanted <<<"${SELECT#,}"
    for w in "${wanted[@]}"; do
        [ -z "$w" ] && continue
        found=0
        for s in "${STEPS[@]}"; do [ "$(field "$s" 0)" = "$w" ] && found=1; done
        [ "$found" = 1 ] || { echo "figures.sh: no step '$w' (--list shows them)" >&2; exit 2; }
    done
    for s in "${STEPS[@]}"; do
        name=$(field "$s" 0); kinds=$(field "$s" 1); slow=$(field "$s" 3)
        pick=0
        if [ -n "${SELECT#,}" ] || [ -n "$KIND" ]; then
            [[ ",${SELECT#,}," == *",$name,"* ]] && pick=1
            IFS=',' read -r -a ks <<<"${KIND#,}"
            for k in "${ks[@]}"; do [ -n "$k" ] && [[ ",$kinds," == *",$k,"* ]] && [ "$slow" = - ] && pick=1; done
        else
            { [ "$slow" = - ] || [ "$SLOW" = 1 ]; } && pick=1
        fi
        [ "$pick" = 1 ] && chosen+=("$name")
    done
    [ ${#chosen[@]} -gt 0 ] || { echo "figures.sh: no step selected" >&2; exit 2; }

    ML="$BUILD/manylights"
    if [ "$DRY" = 0 ] && [ ! -x "$ML" ]; then
        echo "figures.sh: $ML not found: build first (cmake -S . -B $BUILD -DCMAKE_BUILD_TYPE=Release && cmake --build $BUILD -j2), or --build DIR" >&2
        exit 2
    fi

    status=0
    for name in "${chosen[@]}"; do
        D="$OUT/$name"
        [ "$DRY" = 1 ] || mkdir -p "$D"
        LOG="$D/log.txt"
        if [ "$DRY" = 1 ]; then LOG=/dev/null; else : >"$LOG"; fi
        start=$(date +%s)
        say "== $name ($(date -u '+%Y-%m-%d %H:%M UTC'), $(git rev-parse --short HEAD 2>/dev/null || echo 'no git'))"
        if ( set -euo pipefail; "step_$name" ); then
            took=$(( $(date +%s) - start ))
            say "== $name done in ${took} s"
            [ "$DRY" = 1 ] || grep '^ *|' "$LOG" >"$D/tables.md" || true
            [ -s "$D/tables.md" ] && say "   tables: $D/tables.md"
        else
            say "== $name FAILED (log: $LOG)"
            status=1
        fi
    done
    exit $status
}
main "$@"
