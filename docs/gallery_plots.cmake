# The target gallery-plots (docs/CMakeLists.txt): `nhc simulate SCENE --plot DIR` on the examples
# the gallery shows, each plot copied to docs/gallery/<scene>-<plot>.png (gnuplot's PNG, about
# 20-45 kB). Run it after changing an example or the plots; the gallery page (docs/gallery.md)
# links each picture's scene.
# usage: cmake -DSOURCE_DIR= -DNHC= -DWORK_DIR= -P gallery_plots.cmake
cmake_minimum_required(VERSION 3.20)
set(plots  # scene (under examples/) | plots to keep, comma-separated
  "chaplygin_sleigh|path,drift"
  "knife_edge_incline|coordinates"
  "rolling_disk|path")
file(MAKE_DIRECTORY ${SOURCE_DIR}/docs/gallery)
foreach(entry IN LISTS plots)
  string(REPLACE "|" ";" fields "${entry}")
  list(GET fields 0 scene)
  list(GET fields 1 keep)
  string(REPLACE "," ";" keep "${keep}")
  set(dir ${WORK_DIR}/${scene})
  file(REMOVE_RECURSE ${dir})
  execute_process(COMMAND ${NHC} simulate ${SOURCE_DIR}/examples/${scene}.toml --plot ${dir} -o ${dir}.csv
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "nhc simulate ${scene} --plot failed (${rc})")
  endif()
  foreach(plot IN LISTS keep)
    file(COPY_FILE ${dir}/${plot}.png ${SOURCE_DIR}/docs/gallery/${scene}-${plot}.png)
  endforeach()
endforeach()
