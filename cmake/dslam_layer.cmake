# One static library per layer folder, linking only the layers below it. Every layer includes headers by
# their path from the repository's root ("data/image_frame.h"); tests/layers/layers_check.py holds each folder to
# the layers its library names here, so that an include of a higher layer fails the tests, not only a review.
#
# dslam_layer(<folder> SOURCES <files> [OWN_UNITS <files>] [LAYERS <lower layer folders>] [LIBS <public libraries>]
#             [PRIVATE_LIBS <libraries its headers do not show>])
#
# With DSLAM_UNITY_BUILD (the default) a layer's SOURCES compile in batches of eight (a unity build: each batch
# parses the Eigen, OpenCV and standard headers once, which on two cores halves a fresh build of dslam), and
# OWN_UNITS each on its own: the few files whose templates take most of the compiler's time, so that they run
# in parallel with the batches. Names in anonymous namespaces must then be unique within a layer.
function(dslam_layer folder)
  cmake_parse_arguments(ARG "" "" "SOURCES;OWN_UNITS;LAYERS;LIBS;PRIVATE_LIBS" ${ARGN})
  set(target dslam_${folder})
  add_library(${target} STATIC ${ARG_SOURCES} ${ARG_OWN_UNITS})
  if(DSLAM_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
    set_source_files_properties(${ARG_OWN_UNITS} TARGET_DIRECTORY ${target} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
  endif()
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR})
  foreach(layer IN LISTS ARG_LAYERS)
    target_link_libraries(${target} PUBLIC dslam_${layer})
  endforeach()
  target_link_libraries(${target} PUBLIC ${ARG_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
  string(REPLACE ";" " " layers "${ARG_LAYERS}")
  set_property(GLOBAL APPEND PROPERTY DSLAM_LAYER_TABLE "${folder}: ${layers}")
endfunction()

# A part of a layer built as a shared library of its own and loaded on first use (data/runtime_module.h):
# lib<name>.so beside dslam, where the loader looks first, every symbol hidden but its exported entry, built
# before the layer that calls it.
#
# dslam_runtime_module(<name> CALLER <layer folder> SOURCES <files> LIBS <libraries>
#                      [INCLUDES <system include dirs>] [DEFINITIONS <definitions>])
function(dslam_runtime_module name)
  cmake_parse_arguments(ARG "" "CALLER" "SOURCES;LIBS;INCLUDES;DEFINITIONS" ${ARGN})
  add_library(${name} MODULE ${ARG_SOURCES})
  set_target_properties(${name} PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}
    CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
  if(ARG_INCLUDES)
    target_include_directories(${name} SYSTEM PRIVATE ${ARG_INCLUDES})
  endif()
  target_compile_definitions(${name} PRIVATE ${ARG_DEFINITIONS})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS})
  add_dependencies(dslam_${ARG_CALLER} ${name})
endfunction()

# Writes the table of layers (one line per folder: "folder: lower layers it links") for the layer check.
function(dslam_write_layer_table path)
  get_property(table GLOBAL PROPERTY DSLAM_LAYER_TABLE)
  string(REPLACE ";" "\n" text "${table}")
  file(WRITE ${path} "${text}\n")
endfunction()
