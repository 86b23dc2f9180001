#!/bin/sh
# svo demo as a newcomer runs it, small: the contact sheet exists, the
# output directory is created, and every relMSE the demo prints is the one
# `svo compare` prints for the same files run by hand.
#   demo_check.sh SVO WORKDIR
set -eu
svo="$1"
dir="$2"
rm -rf "$dir"
mkdir -p "$dir"
"$svo" demo --resolution 32 --size 48 --spp 4 --octaves 2 -o "$dir/new/out" > "$dir/demo.txt"
test -s "$dir/new/out/svo-demo.png" && echo "contact sheet written"
for view in far mid close; do
  line=$(grep "^$view " "$dir/demo.txt")
  for kind in prefiltered nearest; do
    if [ "$kind" = prefiltered ]; then
      printed=$(echo "$line" | sed -n 's/.*relMSE \([^ ,]*\).*relMSE .*/\1/p')
    else
      printed=$(echo "$line" | sed -n 's/.*relMSE .*relMSE \([^ ,]*\)$/\1/p')
    fi
    by_hand=$("$svo" compare "$dir/new/out/svo-demo/$view-$kind.exr" "$dir/new/out/svo-demo/$view-reference.exr" |
      sed -n 's/.*relMSE \([^,]*\),.*/\1/p')
    if [ -z "$printed" ] || [ "$printed" != "$by_hand" ]; then
      echo "$view $kind: the demo printed '$printed', svo compare '$by_hand'"
      exit 1
    fi
    echo "$view $kind matches"
  done
done
