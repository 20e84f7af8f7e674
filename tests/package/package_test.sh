#!/bin/sh
# The .deb as a user gets it (tools/package): CPack packs this build, dpkg-deb -x unpacks it
# into a temporary root, and the unpacked tree runs from there, not from /usr: the README's
# clip by the shipped scene's bare name (shortened), the Python module finding the same
# scene, a man page per command and the completion script. Then the package's declared
# dependencies are checked against what the program links.
# Usage: package_test.sh BUILD_DIR OUT_DIR
set -eu
build=$1 out=$(realpath -m "$2")
command -v dpkg-deb >/dev/null && command -v cpack >/dev/null || { echo "skipped: dpkg-deb or cpack missing"; exit 77; }
rm -rf "$out" && mkdir -p "$out/root" "$out/work"
cpack -G DEB -B "$out" --config "$build/CPackConfig.cmake" >/dev/null
deb=$(ls "$out"/clothsim_*.deb)
dpkg-deb -x "$deb" "$out/root"
usr=$out/root/usr
cd "$out/work"  # no scenes here: the bare names must come from the unpacked share/clothsim
"$usr/bin/clothsim" compare drape_smooth --duration 0.3 --video clip.mp4 --quiet
test -s clip.mp4
PYTHONPATH=$usr/lib/python3/dist-packages /usr/bin/python3 -c "
import clothsim
scene = clothsim.load_scene('drape_smooth', duration=0.05)
assert scene.particles == 625, scene
assert clothsim.__file__.startswith('$usr/'), clothsim.__file__
"
for page in clothsim clothsim-run clothsim-compare clothsim-bench clothsim-stability clothsim-golden; do
  test -s "$usr/share/man/man1/$page.1" || { echo "no man page $page.1"; exit 1; }
done
grep -q "complete -o filenames -F _clothsim clothsim" "$usr/share/bash-completion/completions/clothsim"
depends=$(dpkg-deb -f "$deb" Depends)
for lib in libavcodec libyaml-cpp libpng16 libhwy python3-numpy python3-pandas; do
  case $depends in *"$lib"*) ;; *) echo "Depends lacks $lib: $depends"; exit 1 ;; esac
done
echo "package: $deb unpacked and ran from $out/root"
