# `cmake --install` into a temporary prefix, then a project outside the tree (examples/cpp) finds
# the package with find_package(cavesim REQUIRED), builds against it and runs.
# Arguments: the build tree, the source tree, a scratch directory.
set -euo pipefail
BUILD=$1 SRC=$2 SCRATCH=$3
rm -rf "$SCRATCH" && mkdir -p "$SCRATCH" && cd "$SCRATCH"
cmake --install "$BUILD" --prefix "$SCRATCH/prefix" > install.log
for f in include/cavesim/cavesim.h include/cavesim/error.h lib/cmake/cavesim/cavesimConfig.cmake \
  lib/cmake/cavesim/cavesimConfigVersion.cmake lib/cmake/cavesim/cavesimTargets.cmake bin/cavesim; do
  [ -e "prefix/$f" ] || { echo "FAIL: $f not installed"; exit 1; }
done
ls prefix/lib/libcavesim.so* > /dev/null || { echo "FAIL: libcavesim.so not installed"; exit 1; }
# The public headers include nothing heavy.
if grep -E '#include *[<"](openvdb|Eigen|tbb|toml\+\+|nlohmann|boost)' prefix/include/cavesim/*.h; then
  echo "FAIL: a public header includes a dependency"; exit 1
fi
GENERATOR=()
command -v ninja > /dev/null && GENERATOR=(-G Ninja)
cmake -S "$SRC/examples/cpp" -B example "${GENERATOR[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$SCRATCH/prefix" > configure.log
cmake --build example > build.log
example/cave_summary "$SRC/examples/small.toml" stage2.p_rate=0.5 > out.txt
cat out.txt
grep -q "scenario 'small3d', grid 24 x 24 x 8" out.txt
grep -q "breakthrough at iteration" out.txt
# Bad input: exit 2 with the command's message.
set +e
example/cave_summary "$SRC/examples/small.toml" stage2.p_rate=-1 2> err.txt
code=$?
set -e
cat err.txt
[ "$code" -eq 2 ] && grep -q "key 'stage2.p_rate' = -1.0: must be a number in" err.txt
echo "install test: ok"
