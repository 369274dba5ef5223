# Consumes the module as a host engine would and runs the example host (examples/host):
#   MODE=install: `cmake --install` into a fresh prefix, find_package(manylights) against it, build and
#                 run the example; then compile it again from `pkg-config --cflags --libs manylights`.
#   MODE=subdir:  add_subdirectory(<repo>) from the example's project; the consumer's cache must not
#                 hold any test-only package (GTest, Embree, TinyGLTF); build and run the example with
#                 synchronization validation (host_example --sync).
# Arguments: -DMODE= -DSOURCE=<repo> -DBUILD=<this build tree> -DOUT=<scratch dir> [-DLAUNCHER=ccache]
cmake_minimum_required(VERSION 3.25)
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGV}\n${out}\n${err}")
  endif()
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${OUT})
set(configure -S ${SOURCE}/examples/host -B ${OUT}/build -DCMAKE_BUILD_TYPE=Release)
if(LAUNCHER)
  list(APPEND configure -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER} -DCMAKE_C_COMPILER_LAUNCHER=${LAUNCHER})
endif()

if(MODE STREQUAL "install")
  run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${OUT}/prefix)
  foreach(f include/manylights/manylights.h include/manylights/module.h include/manylights/types.h
            include/manylights/glm.h include/manylights/manylights.glsl
            lib/cmake/manylights/manylights-config.cmake
            lib/cmake/manylights/manylights-config-version.cmake lib/pkgconfig/manylights.pc)
    if(NOT EXISTS ${OUT}/prefix/${f})
      message(FATAL_ERROR "cmake --install did not install ${f}")
    endif()
  endforeach()
  run(${CMAKE_COMMAND} ${configure} -DCMAKE_PREFIX_PATH=${OUT}/prefix)
elseif(MODE STREQUAL "subdir")
  run(${CMAKE_COMMAND} ${configure} -DMANYLIGHTS_SOURCE_DIR=${SOURCE})
  file(STRINGS ${OUT}/build/CMakeCache.txt test_only REGEX "^(GTest|embree|TinyGLTF)_DIR:")
  if(test_only)
    message(FATAL_ERROR "add_subdirectory looked for test-only packages: ${test_only}")
  endif()
else()
  message(FATAL_ERROR "MODE must be install or subdir")
endif()
run(${CMAKE_COMMAND} --build ${OUT}/build -j2)
# The subdirectory build runs the example under synchronization validation too (hazards between the
# host's commands and the module's, across the two frames in flight); the install build under core
# validation. Either fails on any message its own messenger counts.
if(MODE STREQUAL "subdir")
  run(${OUT}/build/host_example --sync)
else()
  run(${OUT}/build/host_example)
endif()
message("${last_output}")

# Nothing of the package's own settings leaks into the host's target: no GLM_FORCE_* or
# GLM_ENABLE_EXPERIMENTAL definitions, no GLFW on a headless host's link line, and (installed) no
# generic folder of the module (engine/, io/, shaders/) on its include path: include/ only.
file(GLOB_RECURSE flag_files ${OUT}/build/CMakeFiles/host_example.dir/flags.make)
file(GLOB_RECURSE link_files ${OUT}/build/CMakeFiles/host_example.dir/link.txt)
if(NOT flag_files OR NOT link_files)
  message(FATAL_ERROR "no flags.make / link.txt for host_example under ${OUT}/build")
endif()
file(READ ${flag_files} host_flags)
file(READ ${link_files} host_link)
if(host_flags MATCHES "GLM_FORCE|GLM_ENABLE_EXPERIMENTAL")
  message(FATAL_ERROR "the package pushed GLM definitions into the host's target:\n${host_flags}")
endif()
if(host_link MATCHES "glfw")
  message(FATAL_ERROR "a headless host is linked against GLFW:\n${host_link}")
endif()
if(MODE STREQUAL "install" AND host_flags MATCHES "include/manylights")
  message(FATAL_ERROR "the installed package puts include/manylights (its generic folders) on the host's path:\n${host_flags}")
endif()

if(MODE STREQUAL "install")
  # pkg-config: the same program from the .pc file's flags alone (linked, not run again).
  find_program(PKG_CONFIG pkg-config REQUIRED)
  set(ENV{PKG_CONFIG_PATH} ${OUT}/prefix/lib/pkgconfig)
  run(${PKG_CONFIG} --cflags --libs manylights)
  # Nor the language mode: -std= is the host's, on its own compile line.
  if(last_output MATCHES "GLM_|glfw|include/manylights|-std=")
    message(FATAL_ERROR "pkg-config manylights leaks settings into the host: ${last_output}")
  endif()
  separate_arguments(flags UNIX_COMMAND "${last_output}")
  run(c++ -std=c++20 -I${OUT}/build ${SOURCE}/examples/host/main.cpp ${SOURCE}/examples/host/host_device.cpp
      ${flags} -o ${OUT}/host_example_pkgconfig)
  # The CMake package carries C++20 as a usage requirement instead (the example sets no standard of
  # its own): the exported target names cxx_std_20.
  file(GLOB targets_files ${OUT}/prefix/lib/cmake/manylights/manylightsTargets.cmake)
  file(READ ${targets_files} exported)
  string(REGEX MATCH "set_target_properties\\(manylights::manylights PROPERTIES[^)]*\\)" module_props "${exported}")
  if(NOT module_props MATCHES "INTERFACE_COMPILE_FEATURES \"cxx_std_20\"")
    message(FATAL_ERROR "the installed manylights::manylights does not require cxx_std_20:\n${module_props}")
  endif()
  # The public folder only: include/manylights/ holds exactly the source tree's include/manylights/*.h
  # and the generated manylights.glsl, no folder of the module's internal layout (engine/, gpu/, io/,
  # shaders/, shadows/); and every installed header compiles on its own: nothing it needs is missing.
  file(GLOB installed_entries LIST_DIRECTORIES true RELATIVE ${OUT}/prefix/include/manylights
       ${OUT}/prefix/include/manylights/*)
  file(GLOB public_headers RELATIVE ${SOURCE}/include/manylights ${SOURCE}/include/manylights/*.h)
  set(expected ${public_headers} manylights.glsl)
  list(SORT installed_entries)
  list(SORT expected)
  if(NOT installed_entries STREQUAL expected)
    message(FATAL_ERROR "include/manylights/ is not the public folder:\n  installed: ${installed_entries}\n  expected: ${expected}")
  endif()
  # The host-shader include, installed: compiles on its own with -I<prefix>/include only.
  find_program(GLSLANG glslangValidator REQUIRED)
  run(${CMAKE_COMMAND} -DINCLUDE=${OUT}/prefix/include -DGLSLANG=${GLSLANG} -DOUT=${OUT}/host_shaders
      -P ${SOURCE}/tests/packaging/host_shader_include.cmake)
  message("${last_output}")
  file(GLOB_RECURSE installed RELATIVE ${OUT}/prefix/include/manylights ${OUT}/prefix/include/manylights/*.h)
  list(LENGTH installed count)
  message("installed headers compiled on their own: ${count}")
  foreach(h ${installed})
    file(WRITE ${OUT}/alone.cpp "#include <manylights/${h}>\n")
    run(c++ -std=c++20 -fsyntax-only ${flags} ${OUT}/alone.cpp)
  endforeach()
endif()
