# cmake -DSOURCE=<Mod/CurvedSlicer> -DDESTINATION=<build-tree copy> -P sync_workbench.cmake
# Copies the workbench's files into the build tree and removes the files there that the source no
# longer has (a moved or deleted module would otherwise stay importable from the build tree).
# Only workbench files are considered: the compiled module beside them stays.
file(GLOB_RECURSE copied RELATIVE ${DESTINATION}
     ${DESTINATION}/*.py ${DESTINATION}/*.xml ${DESTINATION}/*.svg ${DESTINATION}/*.ui
     ${DESTINATION}/*.md)
foreach(file IN LISTS copied)
  if(NOT EXISTS ${SOURCE}/${file})
    file(REMOVE ${DESTINATION}/${file})
  endif()
endforeach()
file(COPY ${SOURCE}/ DESTINATION ${DESTINATION} PATTERN __pycache__ EXCLUDE)
