# spall_module(<folder> [DEPENDS <module>...] [LIBRARIES <lib>...] [PRIVATE_LIBRARIES <lib>...])
# A module is the folder src/spall/<folder>: a static library spall_<folder with _ for /> (an
# interface library when it has headers only) that links the modules it DEPENDS on. Its rules
# (which modules it may include, transitively) go to module_arrows.txt for the arrow check.
function(spall_module folder)
  cmake_parse_arguments(M "" "" "DEPENDS;LIBRARIES;PRIVATE_LIBRARIES" ${ARGN})
  string(REPLACE "/" "_" name "${folder}")
  set(target spall_${name})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/spall/${folder}/*.cpp)
  set(links ${M_LIBRARIES})
  foreach(dep ${M_DEPENDS})
    string(REPLACE "/" "_" dep_name "${dep}")
    list(APPEND links spall_${dep_name})
  endforeach()
  if(sources)
    add_library(${target} STATIC ${sources})
    target_include_directories(${target} PUBLIC ${CMAKE_SOURCE_DIR}/src ${CMAKE_BINARY_DIR}/generated)
    target_link_libraries(${target} PUBLIC ${links} PRIVATE ${M_PRIVATE_LIBRARIES})
    add_dependencies(${target} spall_module_arrows)
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${CMAKE_SOURCE_DIR}/src ${CMAKE_BINARY_DIR}/generated)
    target_link_libraries(${target} INTERFACE ${links})
  endif()
  # The modules this one may include: itself and, transitively, what it depends on.
  set(allowed ${folder})
  foreach(dep ${M_DEPENDS})
    get_property(dep_allowed GLOBAL PROPERTY SPALL_MODULE_ALLOWS_${dep})
    if(NOT DEFINED dep_allowed OR "${dep_allowed}" STREQUAL "")
      message(FATAL_ERROR "spall_module(${folder}): ${dep} must be declared before the modules that use it")
    endif()
    list(APPEND allowed ${dep_allowed})
  endforeach()
  list(REMOVE_DUPLICATES allowed)
  set_property(GLOBAL PROPERTY SPALL_MODULE_ALLOWS_${folder} "${allowed}")
  set_property(GLOBAL APPEND PROPERTY SPALL_MODULES ${folder})
  set_property(GLOBAL APPEND PROPERTY SPALL_MODULE_TARGETS ${target})
endfunction()

# The arrow check's rules, one line a module ("folder: allowed folders"), and the umbrella
# library `spall` (every module) for the CLI, the tests and the benchmarks.
function(spall_finish_modules)
  get_property(modules GLOBAL PROPERTY SPALL_MODULES)
  get_property(targets GLOBAL PROPERTY SPALL_MODULE_TARGETS)
  set(rules "")
  foreach(folder ${modules})
    get_property(allowed GLOBAL PROPERTY SPALL_MODULE_ALLOWS_${folder})
    string(REPLACE ";" " " allowed "${allowed}")
    string(APPEND rules "${folder}: ${allowed}\n")
  endforeach()
  file(WRITE ${CMAKE_BINARY_DIR}/module_arrows.txt "${rules}")
  add_library(spall INTERFACE)
  target_link_libraries(spall INTERFACE ${targets})
endfunction()

# Runs at every build, before any module compiles.
add_custom_target(spall_module_arrows ALL
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${CMAKE_SOURCE_DIR} -DRULES=${CMAKE_BINARY_DIR}/module_arrows.txt
          -P ${CMAKE_SOURCE_DIR}/cmake/check_module_arrows.cmake
  COMMENT "Checking the module arrows (docs/ARCHITECTURE.md)")
