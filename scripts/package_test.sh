#!/usr/bin/env bash
# The installed package, as a user sees it: configures Unison with its defaults (library and the unison tool only),
# builds and installs it to a temporary prefix, then builds the two examples (examples/hello.cpp, examples/hello.c)
# against the installed package once with find_package(unison) and once with pkg-config (shared library), and the
# C example once more against the static library (pkg-config --static), runs them all and checks that every build
# prints the same ray hit and state hash. Also checks the installed tool and builds the Debian package (cpack).
# Usage: scripts/package_test.sh              (build folder: build-package/, kept; -j2; about 6 min from scratch)
#        scripts/package_test.sh --from DIR   (install and package an already built tree instead, e.g. build/ after
#                                              scripts/test.sh: the same library and tool, built with the same
#                                              Release flags; the default configuration is still configured in
#                                              build-package/, but not built. About 10 s: what CI runs.)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
tree=build-package
if [ "${1:-}" = "--from" ]; then
  tree=${2:?usage: scripts/package_test.sh [--from BUILD_DIR]}
  [ -f "$tree/CMakeCache.txt" ] || { echo "error: $tree is not a configured build folder" >&2; exit 2; }
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"

# The README shows the examples verbatim: the block after each "<!-- examples/FILE" marker must be that file.
status=0
for f in hello.cpp hello.c; do
  if ! diff <(awk -v f="examples/$f" 'index($0, "<!-- " f ":") == 1 {on = 1; next} on && /^```/ {if (in_block) exit; in_block = 1; next} in_block' README.md) "examples/$f" >/dev/null; then
    echo "error: the README's block for examples/$f differs from the file" >&2
    status=1
  fi
done

echo "== configure the default configuration; build $tree and install it to $prefix" >&2
cmake -S . -B build-package -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" >/dev/null
cmake --build "$tree" -j2 >/dev/null
cmake --install "$tree" --prefix "$prefix" >/dev/null
"$prefix/bin/unison" --help >/dev/null

echo "== the examples with find_package(unison)" >&2
cmake -S examples -B "$work/cmake" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/cmake" -j2 >/dev/null

echo "== the examples with pkg-config" >&2
pcdir=$(dirname "$(find "$prefix" -name unison.pc)")
libdir=$(dirname "$pcdir")
export PKG_CONFIG_PATH="$pcdir"
# shellcheck disable=SC2046
g++ -std=c++17 examples/hello.cpp $(pkg-config --cflags --libs unison) -Wl,-rpath,"$libdir" -o "$work/hello_cpp"
# shellcheck disable=SC2046
gcc -std=c99 -Wall -Wextra -pedantic -Werror examples/hello.c $(pkg-config --cflags --libs unison) \
  -Wl,-rpath,"$libdir" -o "$work/hello_c"
# The static library: its private dependencies come from pkg-config --static.
static_libs=$(pkg-config --static --libs unison | sed "s|-lunison |$libdir/libunison.a |")
# shellcheck disable=SC2086
gcc -std=c99 examples/hello.c $(pkg-config --cflags unison) $static_libs -o "$work/hello_c_static"

for pair in "cmake/hello_cpp hello_cpp" "cmake/hello_c hello_c" "cmake/hello_c hello_c_static"; do
  read -r a b <<<"$pair"
  out_a=$("$work/$a")
  out_b=$("$work/$b")
  echo "$b: $out_b"
  if [ "$out_a" != "$out_b" ] || ! grep -q "state hash" <<<"$out_a" || ! grep -q "ray hit" <<<"$out_a"; then
    echo "error: $a and $b disagree or printed no hash / ray hit" >&2
    status=1
  fi
done
if ldd "$work/hello_c_static" | grep -q libunison; then
  echo "error: hello_c_static links the shared library" >&2
  status=1
fi

echo "== Debian package" >&2
(cd "$tree" && cpack -G DEB >/dev/null)
deb=$(ls "$tree"/unison_*.deb)
contents=$(dpkg-deb -c "$deb")
for f in include/unison/unison.h include/unison/world3d.h cmake/unison/unisonConfig.cmake pkgconfig/unison.pc \
         libunison.so.0 libunison.a bin/unison; do
  if ! grep -q "$f" <<<"$contents"; then
    echo "error: $deb lacks $f" >&2
    status=1
  fi
done
echo "package_test: $([ $status = 0 ] && echo ok || echo FAILED) ($deb)"
exit $status
