#!/usr/bin/env bash
# Builds the Debian package with CPack from a configured and built tree, then checks it:
#   1. its contents (dpkg-deb -c): the binary, every schema of schemas/, the user scripts, the licence;
#   2. its Depends cover every shared library the binary links (objdump -p NEEDED -> dpkg -S);
#   3. unpacked into a temporary root (dpkg-deb -x), the binary runs and `fogpipe validate` finds the
#      installed results schema next to it (no $FOGPIPE_SCHEMAS_DIR, no source tree);
#   4. a copy of the binary without schemas still validates recordings (their layout is built in),
#      and fails on a results file with exit code 2, naming the folders it tried.
#   tests/pipeline/packaging/package_test.sh BUILD_DIR SOURCE_DIR
# Exit 77 (a ctest skip) when dpkg-deb, dpkg or objdump is missing (not a Debian-like system).
set -euo pipefail
build_dir="$(cd "$1" && pwd)"
source_dir="$(cd "$2" && pwd)"
for tool in cpack dpkg-deb dpkg objdump; do
  command -v "$tool" >/dev/null || { echo "SKIP: $tool not found"; exit 77; }
done
work="$(mktemp -d "${TMPDIR:-/tmp}/fogpipe-package-test.XXXXXX")"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# ---- 1. build the package and list its contents
cpack --config "$build_dir/CPackConfig.cmake" -G DEB -B "$work/out" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log" >&2; fail "cpack failed"; }
deb="$(ls "$work"/out/fogpipe_*.deb 2>/dev/null | head -n 1)"
[ -n "$deb" ] || fail "cpack wrote no fogpipe_*.deb"
echo "package: $(basename "$deb") ($(stat -c %s "$deb") bytes)"
dpkg-deb -c "$deb" | awk '{print $6}' | sed 's|^\./|/|' >"$work/contents"
expected=(/usr/bin/fogpipe /usr/share/doc/fogpipe/copyright /usr/share/doc/fogpipe/LICENSE
          /usr/share/fogpipe/scripts/report.py /usr/share/fogpipe/scripts/plot_sweep.py
          /usr/share/fogpipe/scripts/campaign_report.py
          /usr/share/fogpipe/scripts/slurm/submit_campaign.sh
          /usr/share/fogpipe/scripts/slurm/fogpipe_array.sbatch
          /usr/share/fogpipe/scripts/slurm/fogpipe_merge.sbatch)
for schema in "$source_dir"/schemas/*; do
  expected+=("/usr/share/fogpipe/schemas/$(basename "$schema")")
done
for path in "${expected[@]}"; do
  grep -qx "$path" "$work/contents" || fail "package lacks $path"
done
echo "contents: all ${#expected[@]} expected files present"
[ "$(dpkg-deb -f "$deb" Package)" = fogpipe ] || fail "package name is not fogpipe"

# ---- 2. Depends cover every NEEDED library
dpkg-deb -x "$deb" "$work/root"
fogpipe="$work/root/usr/bin/fogpipe"
depends="$(dpkg-deb -f "$deb" Depends)"
echo "Depends: $depends"
listed=" $(echo "$depends" | tr ',' '\n' | sed 's/(.*)//; s/ //g' | tr '\n' ' ') "
for lib in $(objdump -p "$fogpipe" | awk '$1 == "NEEDED" {print $2}'); do
  path="$(ldd "$fogpipe" | awk -v lib="$lib" '$1 == lib {print $3}')"
  [ -n "$path" ] || fail "cannot resolve $lib"
  owner="$(dpkg -S "$(readlink -f "$path")" 2>/dev/null || dpkg -S "$path" 2>/dev/null || true)"
  owner="${owner%%:*}"
  [ -n "$owner" ] || fail "$lib ($path) belongs to no Debian package"
  [[ "$listed" == *" $owner "* ]] || fail "$lib comes from $owner, which Depends does not list"
  echo "  $lib -> $owner"
done

# ---- 3. the unpacked binary runs and finds its installed schemas
"$fogpipe" --version
"$fogpipe" validate --help >"$work/help.txt" || fail "validate --help failed"
grep -q -- "--schemas" "$work/help.txt" || fail "validate --help does not describe --schemas"
"$fogpipe" simulate --profile paper --duration-s 600 --seed 3 -o "$work/rec.h5" >/dev/null
"$fogpipe" run "$work/rec.h5" -o "$work/out" >/dev/null 2>&1 || fail "the unpacked fogpipe run failed"
results="$work/out/rec.fogpipe.h5"
(cd "$work" && env -u FOGPIPE_SCHEMAS_DIR "$fogpipe" validate "$work/rec.h5" "$results") ||
  fail "the unpacked fogpipe did not validate a recording and a results file with its installed schemas"

# ---- 4. without installed schemas: exit 2 and the folders tried
mkdir -p "$work/lonely/bin"
cp "$fogpipe" "$work/lonely/bin/fogpipe"
(cd "$work" && env -u FOGPIPE_SCHEMAS_DIR "$work/lonely/bin/fogpipe" validate "$work/rec.h5") ||
  fail "a fogpipe without installed schemas did not validate a recording (built-in layout)"
set +e
(cd "$work" && env -u FOGPIPE_SCHEMAS_DIR "$work/lonely/bin/fogpipe" validate "$results") \
  >"$work/lonely.txt" 2>&1
code=$?
set -e
[ "$code" -eq 2 ] || { cat "$work/lonely.txt" >&2; fail "expected exit code 2 without schemas, got $code"; }
grep -q "$work/lonely/bin/../share/fogpipe/schemas" "$work/lonely.txt" ||
  { cat "$work/lonely.txt" >&2; fail "the error does not name the installed-schemas folder tried"; }
grep -q "$source_dir/schemas" "$work/lonely.txt" &&
  { cat "$work/lonely.txt" >&2; fail "a binary outside the build tree looked in the source tree"; }
echo "PASS"
