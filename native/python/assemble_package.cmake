# Assembles the pure-Python package next to the extension: copies SRC into DST and removes the .py files
# DST has that SRC no longer has (a module moved or deleted in the sources must not linger in the build and
# still import).  Run as: cmake -DSRC=... -DDST=... -P assemble_package.cmake
file(GLOB_RECURSE built RELATIVE ${DST} ${DST}/*.py)
foreach(f IN LISTS built)
  if(NOT EXISTS ${SRC}/${f})
    file(REMOVE ${DST}/${f})
  endif()
endforeach()
file(COPY ${SRC}/ DESTINATION ${DST})
