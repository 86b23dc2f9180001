# Shared by the bench scripts (source it): Debian packages on demand and the
# Stanford bunny from libcgal-demo, as OFF and as OBJ (vdb_tool reads OBJ).

# need_packages PACKAGE...: installs those not installed yet (as root or through sudo).
need_packages() {
  local need=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
  done
  if ((${#need[@]})); then
    local sudo=""; [ "$(id -u)" -ne 0 ] && sudo=sudo
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
  fi
}

# extract_bunny DIR: writes DIR/data/meshes/bunny00.off and DIR/bunny.obj (the same triangles).
extract_bunny() {
  tar xzf /usr/share/doc/libcgal-dev/data.tar.gz -C "$1" data/meshes/bunny00.off
  awk 'NF==0{next} /^OFF/{next} !h{nv=$1; nf=$2; h=1; next} nv>0{print "v",$1,$2,$3; nv--; next} nf>0{print "f",$2+1,$3+1,$4+1; nf--}' \
    "$1/data/meshes/bunny00.off" > "$1/bunny.obj"
}
