#!/bin/sh
# Reads a camera file (svo render --save-camera) and prints "focus on
# target" when its focus distance is the eye-target distance (relative
# 1e-4), then "aperture A".
#   camera_focus.sh CAMERA.json
tr -d ' \n' < "$1" | awk -F'[][,:{}"]+' '{
  for (i = 1; i < NF; i++) {
    if ($i == "eye") { ex = $(i + 1); ey = $(i + 2); ez = $(i + 3) }
    if ($i == "target") { tx = $(i + 1); ty = $(i + 2); tz = $(i + 3) }
    if ($i == "focus") f = $(i + 1)
    if ($i == "aperture") a = $(i + 1)
  }
  d = sqrt((ex - tx) ^ 2 + (ey - ty) ^ 2 + (ez - tz) ^ 2)
  if (f > 0 && (f - d) ^ 2 < 1e-8 * d * d) print "focus on target"; else print "focus " f ", distance " d
  print "aperture " a
}'
