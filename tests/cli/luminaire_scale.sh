#!/bin/sh
# --luminaire-scale multiplies the luminaire's light and nothing else: frames
# at scales 1, 2 and 3 (the same samples) differ from the first by 1 and 2
# times one frame of the luminaire's light, so the RMSE of 1 against 3 is
# twice that of 1 against 2. Prints "ratio R" (R to two decimals).
#   luminaire_scale.sh SVO OCTREE LUMINAIRE
set -e
svo=$1
for k in 1 2 3; do
  "$svo" render "$2" --cpu --width 32 --height 32 -o "scale$k.exr" --luminaire "$3" --luminaire-spp 16 \
    --luminaire-scale $k > /dev/null
done
rmse() { "$svo" compare "$1" "$2" | sed -n 's/.*: RMSE \([0-9.e+-]*\),.*/\1/p'; }
a=$(rmse scale1.exr scale3.exr)
b=$(rmse scale1.exr scale2.exr)
awk -v a="$a" -v b="$b" 'BEGIN { if (b > 0) printf "ratio %.2f\n", a / b; else print "no light: RMSE " a ", " b }'
