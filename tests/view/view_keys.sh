#!/bin/sh
# svo view's keys and moving frames under Xvfb, driven by xdotool (labels:
# cli, view). Skipped (exit 77) without xvfb-run or xdotool.
# usage: view_keys.sh CASE SVO IMAGE_CHECK OCTREE OUT_DIR
#   title       the title lists the keys; H prints them on stdout and shows
#               them over the view (its top left darkens), a second H hides them
#   screenshot  P and F12 write svo-view-NNNN.png at the window's size (400 x
#               300, rendered at 200 x 150), numbered after an existing
#               svo-view-0001.png, which is left as it was; each name printed
#   drag        while the left button drags, frames are drawn at the smallest
#               moving size (--frame-budget 1: 85x64 in a 400 x 300 window);
#               once the drag stops, the still view is drawn at --scale (200x150)
set -u
case=$1 svo=$2 check=$3 octree=$4 dir=$5
for tool in xvfb-run xdotool; do
  if ! command -v $tool >/dev/null 2>&1; then
    echo "$tool not found (Debian packages xvfb, xdotool): skipped"
    exit 77
  fi
done
work="$dir/view_keys_$case"
rm -rf "$work"
mkdir -p "$work" || exit 1
# A pre-existing screenshot that must survive.
printf 'keep me\n' >"$work/svo-view-0001.png"

echo "+ xvfb-run -a sh -c 'svo view $octree --width 400 --height 300 --scale 0.5 --frame-budget 1 --screenshot-dir $work & (xdotool: $case)'"
CASE="$case" SVO="$svo" OCTREE="$octree" WORK="$work" xvfb-run -a -s "-screen 0 640x480x24" sh -c '
  "$SVO" view "$OCTREE" --width 400 --height 300 --scale 0.5 --frame-budget 1 --validate \
    --screenshot-dir "$WORK" >"$WORK/stdout.txt" 2>"$WORK/stderr.txt" &
  pid=$!
  window=$(timeout 60 xdotool search --sync --name "^svo view .*prefiltered") || { echo "no window"; kill $pid; exit 1; }
  title() { xdotool getwindowname "$window"; }
  # wait_title PATTERN WHAT: until the title matches (60 s at most)
  wait_title() {
    tries=0
    until title | grep -q -e "$1"; do
      tries=$((tries + 1))
      [ $tries -lt 600 ] || { echo "$2: the title stayed \"$(title)\""; kill $pid; exit 1; }
      sleep 0.1
    done
  }
  # wait_stdout PATTERN WHAT: until the viewer printed a line matching (60 s at most)
  wait_stdout() {
    tries=0
    until grep -q -e "$1" "$WORK/stdout.txt"; do
      tries=$((tries + 1))
      [ $tries -lt 600 ] || { echo "$2: stdout is \"$(cat "$WORK/stdout.txt")\""; kill $pid; exit 1; }
      sleep 0.1
    done
  }
  wait_title "200x150" "first frame"
  case $CASE in
    title)
      echo "title: $(title)"
      title | grep -q "H keys, P screenshot, Q quit" || { echo "the title does not list the keys"; kill $pid; exit 1; }
      # The overlay: the window'"'"'s top left darkens with white text on H, and
      # is as before on the second H (where ImageMagick can capture the window).
      capture() {  # NAME: the window as NAME.png
        sleep 1.5
        import -window "$window" "$WORK/$1.png"
      }
      differ() {  # A B: the mean absolute difference of the top-left 180 x 110 pixels, 0 to 1
        convert "$WORK/$1.png" "$WORK/$2.png" -compose difference -composite -crop 180x110+0+0 -format "%[fx:mean]" info:
      }
      magick=""
      command -v import >/dev/null 2>&1 && command -v convert >/dev/null 2>&1 && capture before && magick=yes
      xdotool key --window "$window" h
      wait_stdout "^Keys: " "H"
      grep -q "P or F12 screenshot" "$WORK/stdout.txt" || { echo "H printed no screenshot key"; kill $pid; exit 1; }
      if [ -n "$magick" ]; then
        # until_differ NAME TEST: capture NAME until its difference from the
        # view before H passes awk TEST on d (30 s at most: frames are slow under load)
        until_differ() {
          tries=0
          while :; do
            capture "$1"
            d=$(differ before "$1")
            awk -v d="$d" "BEGIN { exit !($2) }" && break
            tries=$((tries + 1))
            [ $tries -lt 20 ] || { echo "$1: top left differs by $d from the view before H"; kill $pid; exit 1; }
          done
        }
        until_differ shown "d > 0.03"
        shown=$d
        xdotool key --window "$window" h
        until_differ hidden "d < 0.005"
        echo "top left against the view before H: $shown with the keys shown, $d hidden again"
      else
        echo "ImageMagick (import, convert) not found: overlay part skipped"
      fi
      ;;
    screenshot)
      xdotool key --window "$window" p
      wait_stdout "svo-view-0002.png" "P"
      xdotool key --window "$window" F12
      wait_stdout "svo-view-0003.png" "F12"
      ;;
    drag)
      xdotool mousemove --window "$window" 200 150 mousedown 1
      i=0
      seen=""
      while [ $i -lt 100 ]; do
        xdotool mousemove_relative 3 0
        title | grep -q "| native [^|]*, 85x64," && { seen=yes; break; }
        title | grep -q "| GPU [^|]*, 85x64," && { seen=yes; break; }
        i=$((i + 1))
        sleep 0.05
      done
      xdotool mouseup 1
      [ -n "$seen" ] || { echo "no moving frame at 85x64 during the drag: \"$(title)\""; kill $pid; exit 1; }
      echo "during the drag: $(title)"
      wait_title ", 200x150," "after the drag"
      echo "after the drag: $(title)"
      ;;
  esac
  xdotool key --window "$window" q
  wait $pid
  status=$?
  [ $status -eq 0 ] || { echo "svo view exited with $status: $(cat "$WORK/stderr.txt")"; exit 1; }
' || exit 1
echo "stdout of svo view:"
cat "$work/stdout.txt"
if [ "$case" = screenshot ]; then
  [ "$(cat "$work/svo-view-0001.png")" = "keep me" ] || { echo "svo-view-0001.png was replaced"; exit 1; }
  for n in 2 3; do
    grep -q "^screenshot $work/svo-view-000$n.png (400 x 300)\$" "$work/stdout.txt" ||
      { echo "no line 'screenshot $work/svo-view-000$n.png (400 x 300)'"; exit 1; }
    "$check" "$work/svo-view-000$n.png" 400 300 || exit 1
  done
  [ ! -e "$work/svo-view-0004.png" ] || { echo "svo-view-0004.png written: one screenshot too many"; exit 1; }
fi
echo "OK"
