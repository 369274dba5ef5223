#!/bin/sh
# demo --window driven by real X input events (xdotool through XTEST, under xvfb-run): 3 and 2 switch
# the culling mode, W held moves the camera, a mouse drag turns it, the title shows per-pass times,
# Esc closes the window and the demo exits 0 having printed a different end camera.
# Usage (run under xvfb-run): window_keys.sh MANYLIGHTS_EXE OUT_DIR
set -u
exe=$1
out=$2
mkdir -p "$out"
log=$out/window_keys.log
"$exe" demo --window --frames 0 --size 160x90 --lights 32 --out "$out" >"$log" 2>&1 &
demo=$!
fail() {
  echo "window_keys: $1"
  cat "$log"
  kill "$demo" 2>/dev/null
  exit 1
}
wid=$(timeout 30 xdotool search --sync --name '^manylights' | head -n 1)
[ -n "$wid" ] || fail "no window appeared"
# The first frame's report sets the per-pass title.
i=0
until xdotool getwindowname "$wid" | grep -q 'evaluate [0-9.]* |.* total'; do
  i=$((i + 1)); [ $i -lt 150 ] || fail "title never showed per-pass times: $(xdotool getwindowname "$wid")"
  sleep 0.2
done
echo "title: $(xdotool getwindowname "$wid")"
xdotool windowfocus --sync "$wid" 2>/dev/null || true
xdotool key 3
sleep 0.5
xdotool key 2
xdotool keydown w
sleep 1.5
xdotool keyup w
xdotool mousemove --window "$wid" 80 45 mousedown 1
sleep 0.5
xdotool mousemove_relative 40 0
sleep 1
xdotool mouseup 1
sleep 0.5
xdotool key Escape
i=0
while kill -0 "$demo" 2>/dev/null; do
  i=$((i + 1)); [ $i -lt 150 ] || fail "Esc did not close the window"
  sleep 0.2
done
wait "$demo" || fail "demo exited non-zero"
grep -q '^window: culling none' "$log" || fail "key 3 did not switch to no culling"
grep -q '^window: culling tiled' "$log" || fail "key 2 did not switch to tiled culling"
start=$(sed -n 's/^window: start camera \([^ ]*\).*/\1/p' "$log")
end=$(sed -n 's/^window: end camera \([^ ]*\).*/\1/p' "$log")
[ -n "$start" ] && [ -n "$end" ] || fail "no start/end camera line"
echo "camera: $start -> $end"
# W moved the position (first three numbers); the drag turned the view (target - position).
echo "$start $end" | tr ',' ' ' | awk '{
  moved = ($1-$7)^2 + ($2-$8)^2 + ($3-$9)^2;
  turned = (($4-$1)-($10-$7))^2 + (($5-$2)-($11-$8))^2 + (($6-$3)-($12-$9))^2;
  exit !(moved > 1 && turned > 0.001) }' || fail "W did not move or the mouse drag did not turn the camera"
cat "$log" | grep '^window:'
exit 0
