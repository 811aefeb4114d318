# All dependencies come from Debian 12 packages (scripts/setup.sh installs them).
# Order matters: TBB's config first, else OpenVDB's FindTBB defines TBB::tbb itself.
find_package(TBB 2021 CONFIG REQUIRED)
find_package(Boost 1.74 CONFIG REQUIRED)
find_package(OpenMesh CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(tomlplusplus CONFIG REQUIRED)
find_package(nlohmann_json 3.11 CONFIG REQUIRED)
find_package(PNG REQUIRED)
find_package(ZLIB REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(TinyGLTF CONFIG REQUIRED)
list(APPEND CMAKE_MODULE_PATH /usr/lib/x86_64-linux-gnu/cmake/OpenVDB)
find_package(OpenVDB 10 REQUIRED)
if(CAVESIM_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
  include(GoogleTest)
endif()
if(CAVESIM_BUILD_BENCH)
  find_package(benchmark CONFIG REQUIRED)
endif()
# FindOpenVDB switches BUILD_SHARED_LIBS on for the whole project; cavesim's own modules are
# static libraries linked into one self-contained `cavesim` executable.
set(BUILD_SHARED_LIBS OFF)
# Cairo draws the text of every picture (DejaVu Sans through fontconfig) and the cave maps (PNG and SVG).
find_package(PkgConfig REQUIRED)
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo cairo-svg)
