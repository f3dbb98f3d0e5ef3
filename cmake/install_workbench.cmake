# Install step of the workbench, run by `cmake --install <build> --component workbench`
# (freecad_workbench.cmake sets WORKBENCH_SOURCE, WORKBENCH_MODULE, MOD_DIR and FREECADCMD, then
# includes this file). The destination is MOD_DIR when given, else the user Mod folder of the
# installed FreeCAD, asked from FreeCAD itself: getUserAppDataDir()/Mod, which is
# $FREECAD_USER_HOME/ (when that folder exists), ~/.local/share/FreeCAD/ for 0.20 and 1.0, and
# the versioned ~/.local/share/FreeCAD/v1-1/ for 1.1. Without freecadcmd: $FREECAD_USER_HOME/Mod,
# else the newest versioned folder ~/.local/share/FreeCAD/vX-Y/Mod, else ~/.local/share/FreeCAD/Mod.

function(ask_freecad_user_data_dir freecadcmd result)
  set(${result} "" PARENT_SCOPE)
  execute_process(
    COMMAND "${freecadcmd}" -c
            "import FreeCAD; print('CURVEDSLICER-USER-DATA=' + FreeCAD.getUserAppDataDir())"
    OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE status TIMEOUT 120)
  if(out MATCHES "CURVEDSLICER-USER-DATA=([^\r\n]+)")
    string(REGEX REPLACE "/+$" "" folder "${CMAKE_MATCH_1}")
    set(${result} "${folder}" PARENT_SCOPE)
  else()
    message(WARNING "${freecadcmd} did not name its user data folder (exit ${status}): ${out}${err}"
                    "; falling back to the default folders")
  endif()
endfunction()

function(guess_user_mod_dir result)
  if(DEFINED ENV{FREECAD_USER_HOME} AND NOT "$ENV{FREECAD_USER_HOME}" STREQUAL "")
    set(${result} "$ENV{FREECAD_USER_HOME}/Mod" PARENT_SCOPE)
    return()
  endif()
  set(data "$ENV{HOME}/.local/share/FreeCAD")
  file(GLOB versioned LIST_DIRECTORIES true "${data}/v[0-9]*-[0-9]*")
  if(versioned)
    list(SORT versioned COMPARE NATURAL ORDER DESCENDING)
    list(GET versioned 0 newest)
    set(${result} "${newest}/Mod" PARENT_SCOPE)
  else()
    set(${result} "${data}/Mod" PARENT_SCOPE)
  endif()
endfunction()

if(NOT MOD_DIR)
  if(DEFINED ENV{FREECAD_USER_HOME} AND NOT "$ENV{FREECAD_USER_HOME}" STREQUAL "")
    # FreeCAD ignores a FREECAD_USER_HOME that does not exist yet.
    file(MAKE_DIRECTORY "$ENV{FREECAD_USER_HOME}")
  endif()
  if(NOT FREECADCMD OR NOT EXISTS "${FREECADCMD}")
    find_program(FREECADCMD NAMES freecadcmd FreeCADCmd)
  endif()
  if(FREECADCMD)
    ask_freecad_user_data_dir("${FREECADCMD}" user_data)
    if(user_data)
      set(MOD_DIR "${user_data}/Mod")
    endif()
  endif()
  if(NOT MOD_DIR)
    guess_user_mod_dir(MOD_DIR)
  endif()
endif()

message(STATUS "Installing the CurvedSlicer workbench into ${MOD_DIR}/CurvedSlicer")
file(INSTALL "${WORKBENCH_SOURCE}/" DESTINATION "${MOD_DIR}/CurvedSlicer"
     PATTERN __pycache__ EXCLUDE)
file(INSTALL "${WORKBENCH_MODULE}" DESTINATION "${MOD_DIR}/CurvedSlicer/freecad/curvedslicer")
