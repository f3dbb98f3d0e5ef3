# Sourced by scripts/setup.sh and scripts/run_tests.sh so that both configure build/ alike (a
# different launcher would make the second configure rebuild everything). Sets the array
# `launcher` to the CMake argument that puts ccache in front of the compiler when ccache is
# installed: a second run, or a second clone (CCACHE_BASEDIR makes the paths relative), compiles
# only what changed. The sloppiness lets ccache cache sources built with precompiled headers.
# CMAKE_CXX_COMPILER_LAUNCHER in the environment takes precedence (CMake reads it itself);
# CURVEDSLICER_NO_CCACHE=1 builds without ccache.
launcher=()
if [[ "${CURVEDSLICER_NO_CCACHE:-0}" != 1 && -z "${CMAKE_CXX_COMPILER_LAUNCHER:-}" ]] &&
   command -v ccache >/dev/null 2>&1; then
  launcher=("-DCMAKE_CXX_COMPILER_LAUNCHER=env;CCACHE_BASEDIR=$repo;CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime;ccache")
fi
