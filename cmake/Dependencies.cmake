# Every third-party dependency, found once. Each comes from a Debian package installed by
# scripts/install-deps.sh; the message says which package to install when one is missing.

macro(scanplan_require name package)
  find_package(${name} ${ARGN})
  if(NOT ${name}_FOUND)
    message(FATAL_ERROR "scanplan needs ${name}: install the Debian package '${package}' "
                        "(scripts/install-deps.sh installs every dependency)")
  endif()
endmacro()

scanplan_require(OpenCASCADE libocct-data-exchange-dev CONFIG
                 COMPONENTS FoundationClasses ModelingData ModelingAlgorithms
                            Visualization ApplicationFramework DataExchange)
scanplan_require(embree libembree-dev 3 CONFIG)
scanplan_require(Eigen3 libeigen3-dev 3.3 CONFIG NO_MODULE)
scanplan_require(TBB libtbb-dev CONFIG)
scanplan_require(nlohmann_json nlohmann-json3-dev 3 CONFIG)
scanplan_require(CLI11 libcli11-dev CONFIG)
scanplan_require(yaml-cpp libyaml-cpp-dev CONFIG)
scanplan_require(nanoflann libnanoflann-dev CONFIG)
scanplan_require(fmt libfmt-dev CONFIG)
scanplan_require(Open3D libopen3d-dev CONFIG)
# Open3D's ICP runs OpenMP regions; scanplan keeps each check on one thread (icp.cpp).
scanplan_require(OpenMP libgomp1)
find_package(PkgConfig REQUIRED)
pkg_check_modules(CBC IMPORTED_TARGET cbc)
if(NOT CBC_FOUND)
  message(FATAL_ERROR "scanplan needs COIN-OR CBC: install the Debian package 'coinor-libcbc-dev' "
                      "(scripts/install-deps.sh installs every dependency)")
endif()

find_library(QHULL_R qhull_r)
find_path(QHULL_R_INCLUDE libqhull_r/libqhull_r.h)
if(NOT QHULL_R OR NOT QHULL_R_INCLUDE)
  message(FATAL_ERROR "scanplan needs Qhull: install the Debian package 'libqhull-dev' "
                      "(scripts/install-deps.sh installs every dependency)")
endif()
add_library(qhull_r INTERFACE)
target_include_directories(qhull_r SYSTEM INTERFACE ${QHULL_R_INCLUDE})
target_link_libraries(qhull_r INTERFACE ${QHULL_R})

if(SCANPLAN_BUILD_TESTS)
  scanplan_require(GTest libgtest-dev CONFIG)
endif()
if(SCANPLAN_BUILD_BENCH)
  scanplan_require(benchmark libbenchmark-dev CONFIG)
endif()

# OCCT's exported targets carry no include directory.
add_library(scanplan_occt INTERFACE)
target_include_directories(scanplan_occt SYSTEM INTERFACE ${OpenCASCADE_INCLUDE_DIR})
target_link_libraries(scanplan_occt INTERFACE
  TKernel TKMath TKG2d TKG3d TKGeomBase TKBRep TKGeomAlgo TKTopAlgo TKPrim TKBO
  TKShHealing TKMesh TKLCAF TKCAF TKXSBase TKSTEPBase TKSTEP TKIGES TKXCAF TKXDESTEP
  TKXDEIGES TKSTL TKRWMesh TKGeomAlgo TKBinXCAF TKBin TKBinL)

scanplan_require(TinyGLTF libtinygltf-dev CONFIG)
scanplan_require(fcl libfcl-dev CONFIG)
# OMPL's package sets variables, not a target; its library comes first in OMPL_LIBRARIES,
# then the Boost libraries it links itself (whose -dev packages need not be installed).
scanplan_require(ompl libompl-dev CONFIG)
list(GET OMPL_LIBRARIES 0 SCANPLAN_OMPL_LIBRARY)
add_library(scanplan_ompl INTERFACE)
target_include_directories(scanplan_ompl SYSTEM INTERFACE ${OMPL_INCLUDE_DIRS})
target_link_libraries(scanplan_ompl INTERFACE ${SCANPLAN_OMPL_LIBRARY})
pkg_check_modules(STB IMPORTED_TARGET stb)
if(NOT STB_FOUND)
  message(FATAL_ERROR "scanplan needs stb: install the Debian package 'libstb-dev' "
                      "(scripts/install-deps.sh installs every dependency)")
endif()

# The report's 3D viewer is bundled with three.js by esbuild, both from the npm registry
# (web/package.json, installed by scripts/install-deps.sh with npm ci).
# The platform's own esbuild binary first (it runs even where npm skipped install scripts).
file(GLOB esbuild_platform_bins ${PROJECT_SOURCE_DIR}/web/node_modules/@esbuild/*/bin)
find_program(SCANPLAN_ESBUILD esbuild
             PATHS ${esbuild_platform_bins} ${PROJECT_SOURCE_DIR}/web/node_modules/.bin
             NO_DEFAULT_PATH)
if(NOT SCANPLAN_ESBUILD)
  message(FATAL_ERROR "scanplan needs the report's web packages: run scripts/install-deps.sh "
                      "(it runs npm ci in web/)")
endif()
