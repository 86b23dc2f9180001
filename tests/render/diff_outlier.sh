#!/bin/sh
# svo compare --diff on an image with small errors everywhere and one outlier
# (issue 21): the default scale is the 99th percentile, not the outlier, so
# the diff shows the small errors (svo_image_check finds a picture) where the
# largest error as the scale (--diff-percentile 100) leaves it black; the
# diff holds the image and the colour bar under it (16 x 400 + 27 rows).
# The image is tall so that the bar alone stays under svo_image_check's 5 %.
# Usage: diff_outlier.sh SVO IMAGE_CHECK DIR
set -e
svo=$1 check=$2 dir=$3
rm -rf "$dir"
mkdir -p "$dir"
cd "$dir"
awk 'BEGIN { print "P3\n16 400\n255"; for (y = 0; y < 400; y++) for (x = 0; x < 16; x++) print 128, 128, 128 }' > ref.ppm
# Errors of 0, 2 and 4 codes; the top-left pixel exact (black in the diff); one pixel off by 127.
awk 'BEGIN { print "P3\n16 400\n255"; for (y = 0; y < 400; y++) for (x = 0; x < 16; x++) {
  v = (x == 3 && y == 5) ? 255 : 128 + 2 * ((x + y) % 3); print v, v, v } }' > img.ppm
"$svo" compare img.ppm ref.ppm --diff diff.png | sed 's/.*; /; /'
"$check" diff.png 16 427
"$svo" compare img.ppm ref.ppm --diff max.png --diff-percentile 100 | sed 's/.*; /; /'
if "$check" max.png 16 427; then echo "the largest error as the scale shows the small errors"; exit 1; fi
echo ok
