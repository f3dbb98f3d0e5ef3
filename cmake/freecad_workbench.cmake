# The FreeCAD workbench: a build-tree copy of Mod/CurvedSlicer next to the compiled module (so
# FreeCAD loads exactly what `cmake --install` would install), the install rule into the user's
# Mod folder, and the freecadcmd / xvfb GUI tests.

# ---- build-tree copy ------------------------------------------------------------------------
# (files deleted or moved in the source are removed from the copy too: sync_workbench.cmake)
set(workbench_source ${PROJECT_SOURCE_DIR}/Mod/CurvedSlicer)
file(GLOB_RECURSE workbench_files CONFIGURE_DEPENDS
     ${workbench_source}/*.py ${workbench_source}/*.xml ${workbench_source}/*.svg
     ${workbench_source}/*.ui ${workbench_source}/*.md)
set(workbench_stamp ${CMAKE_BINARY_DIR}/workbench.stamp)
add_custom_command(
  OUTPUT ${workbench_stamp}
  COMMAND ${CMAKE_COMMAND} -DSOURCE=${workbench_source}
          -DDESTINATION=${CURVEDSLICER_WORKBENCH_BUILD_DIR}
          -P ${PROJECT_SOURCE_DIR}/cmake/sync_workbench.cmake
  COMMAND ${CMAKE_COMMAND} -E touch ${workbench_stamp}
  DEPENDS ${workbench_files} ${PROJECT_SOURCE_DIR}/cmake/sync_workbench.cmake
  COMMENT "Copying the FreeCAD workbench into ${CURVEDSLICER_WORKBENCH_BUILD_DIR}")
add_custom_target(curvedslicer_workbench ALL DEPENDS ${workbench_stamp} _curvedslicer)

# ---- install into the user's Mod folder -------------------------------------------------------
# `cmake --install <build> --component workbench` installs only the workbench. Destination,
# decided at install time (cmake/install_workbench.cmake): CURVEDSLICER_FREECAD_MOD_DIR if set at
# configure time, else the user Mod folder FreeCAD names (getUserAppDataDir()/Mod: 0.20 and 1.0
# ~/.local/share/FreeCAD/Mod, 1.1 ~/.local/share/FreeCAD/v1-1/Mod, or $FREECAD_USER_HOME/Mod).
set(CURVEDSLICER_FREECAD_MOD_DIR "" CACHE PATH
    "FreeCAD Mod folder to install the workbench into (empty: the user's, at install time)")
find_program(FREECADCMD_EXECUTABLE NAMES freecadcmd FreeCADCmd)
install(CODE "
  set(WORKBENCH_SOURCE \"${workbench_source}\")
  set(WORKBENCH_MODULE \"$<TARGET_FILE:_curvedslicer>\")
  set(MOD_DIR \"${CURVEDSLICER_FREECAD_MOD_DIR}\")
  set(FREECADCMD \"${FREECADCMD_EXECUTABLE}\")
  include(\"${PROJECT_SOURCE_DIR}/cmake/install_workbench.cmake\")
" COMPONENT workbench)

# ---- tests ----------------------------------------------------------------------------------
# Each test runs in its own FREECAD_USER_HOME (under the build folder; its Mod links to the
# build-tree workbench), so tests never touch the real user configuration and can run in
# parallel. The driver fails on a non-zero exit, a missing success marker or any "Traceback".
if(CURVEDSLICER_BUILD_TESTS)
  find_program(FREECAD_EXECUTABLE freecad)
  find_program(XVFB_RUN_EXECUTABLE xvfb-run)
  set(driver ${PROJECT_SOURCE_DIR}/tests/freecad/run_in_freecad.py)
  if(FREECADCMD_EXECUTABLE)
    file(GLOB freecad_tests CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/freecad/test_*.py)
    foreach(test_file IN LISTS freecad_tests)
      get_filename_component(test_name ${test_file} NAME_WE)
      add_test(NAME freecad_${test_name}
               COMMAND ${Python3_EXECUTABLE} ${driver} --mode headless
                       --freecad ${FREECADCMD_EXECUTABLE}
                       --home ${CMAKE_BINARY_DIR}/freecad-test-homes/${test_name}
                       --mod ${CURVEDSLICER_FREECAD_HOME}/Mod --script ${test_file})
      set_tests_properties(freecad_${test_name} PROPERTIES LABELS freecad TIMEOUT 900
                           ENVIRONMENT "OMP_NUM_THREADS=2")
    endforeach()
    # The install rule: a fresh HOME, `cmake --install`, then FreeCAD loads the installed copy.
    add_test(NAME freecad_install_rule
             COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tests/freecad/install_check.py
                     --cmake ${CMAKE_COMMAND} --build ${CMAKE_BINARY_DIR}
                     --freecadcmd ${FREECADCMD_EXECUTABLE}
                     --home ${CMAKE_BINARY_DIR}/freecad-test-homes/install_rule)
    set_tests_properties(freecad_install_rule PROPERTIES LABELS freecad TIMEOUT 300
                         PASS_REGULAR_EXPRESSION "CURVEDSLICER-TESTS-OK")
  else()
    message(STATUS "freecadcmd not found: FreeCAD headless tests skipped")
  endif()
  if(FREECAD_EXECUTABLE AND XVFB_RUN_EXECUTABLE)
    file(GLOB gui_tests CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/gui/test_*.py)
    foreach(test_file IN LISTS gui_tests)
      get_filename_component(test_name ${test_file} NAME_WE)
      add_test(NAME gui_${test_name}
               COMMAND ${Python3_EXECUTABLE} ${driver} --mode gui --freecad ${FREECAD_EXECUTABLE}
                       --xvfb-run ${XVFB_RUN_EXECUTABLE}
                       --home ${CMAKE_BINARY_DIR}/freecad-test-homes/gui_${test_name}
                       --mod ${CURVEDSLICER_FREECAD_HOME}/Mod --script ${test_file})
      set_tests_properties(gui_${test_name} PROPERTIES LABELS gui TIMEOUT 900
                           ENVIRONMENT "OMP_NUM_THREADS=2")
    endforeach()
  else()
    message(STATUS "freecad or xvfb-run not found: FreeCAD GUI tests skipped")
  endif()
endif()
