# One static library per layer folder, linking only the layers below it. Every layer includes headers by
# their path from the repository's root ("data/image_frame.h"); tests/layers/layers_check.py holds each folder to
# the layers its library names here, so that an include of a higher layer fails the tests, not only a review.
#
# dslam_layer(<folder> SOURCES <files> [LAYERS <lower layer folders>] [LIBS <public libraries>]
#             [PRIVATE_LIBS <libraries its headers do not show>])
function(dslam_layer folder)
  cmake_parse_arguments(ARG "" "" "SOURCES;LAYERS;LIBS;PRIVATE_LIBS" ${ARGN})
  set(target dslam_${folder})
  add_library(${target} STATIC ${ARG_SOURCES})
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR})
  foreach(layer IN LISTS ARG_LAYERS)
    target_link_libraries(${target} PUBLIC dslam_${layer})
  endforeach()
  target_link_libraries(${target} PUBLIC ${ARG_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
  string(REPLACE ";" " " layers "${ARG_LAYERS}")
  set_property(GLOBAL APPEND PROPERTY DSLAM_LAYER_TABLE "${folder}: ${layers}")
endfunction()

# Writes the table of layers (one line per folder: "folder: lower layers it links") for the layer check.
function(dslam_write_layer_table path)
  get_property(table GLOBAL PROPERTY DSLAM_LAYER_TABLE)
  string(REPLACE ";" "\n" text "${table}")
  file(WRITE ${path} "${text}\n")
endfunction()
