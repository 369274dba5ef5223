# The layering check: apps/, host/ and examples/host use the module only through its public
# headers. Every quoted #include of their files must match the allow-list below; anything else (engine
# internals such as module_impl.h, device.h, program.h, resources.h, profiler.h, gbuffer.h; lights/,
# culling/, shadows/gpu/, shadows/virtual/ except its settings) fails the test with file, line and header.
#   cmake -DSOURCE=<repo> [-DDIRS=dir1;dir2] -P tests/packaging/public_includes.cmake
if(NOT SOURCE)
  message(FATAL_ERROR "public_includes.cmake: pass -DSOURCE=<repository root>")
endif()
if(NOT DIRS)
  set(DIRS apps host examples/host)
endif()

# Regular expressions of the headers apps and hosts may include.
set(ALLOWED
  # the public API (installed: include/manylights/), the project's tools' read-backs (not installed),
  # ML_VK_CHECK
  "^manylights/[a-z_]+\\.h$" "^engine/manylights_diagnostics\\.h$" "^io/result\\.h$" "^gpu/vk_check\\.h$"
  # the device API types' former path: a one-line forward to manylights/device.h
  "^gpu/device_types\\.h$"
  # GPU structs and light math shared by C++ and GLSL (the project's tools; not installed)
  "^shaders/shared/[a-z_]+\\.h$"
  # libraries of their own, below the commands: static shadow encoders and bake files, file
  # io, scenes, the Embree reference, the static shadow commands' GPU tools
  "^shadows/static/[a-z_]+\\.h$" "^io/[a-z_]+\\.h$" "^scenes/[a-z_]+\\.h$" "^bake/[a-z_]+\\.h$" "^bake/reference/[a-z_]+\\.h$"
  "^shadows/tools/[a-z_]+\\.h$"
  # the folders' own headers, examples/host's own (its instance and device) and generated SPIR-V arrays
  "^apps/[a-z_]+\\.h$" "^host/[a-z_]+\\.h$" "^host_device\\.h$" "^host_(gbuffer_vert|gbuffer_frag|lights_comp)\\.h$")

set(bad 0)
set(checked 0)
foreach(dir ${DIRS})
  file(GLOB_RECURSE files ${SOURCE}/${dir}/*.cpp ${SOURCE}/${dir}/*.h ${SOURCE}/${dir}/*.hpp)
  foreach(file ${files})
    file(RELATIVE_PATH rel ${SOURCE} ${file})
    file(READ ${file} text)
    # One list entry per line: characters CMake treats specially in lists are neutralised first.
    string(REPLACE ";" "," text "${text}")
    string(REPLACE "[" "(" text "${text}")
    string(REPLACE "]" ")" text "${text}")
    string(REPLACE "\n" ";" lines "${text}")
    set(number 0)
    foreach(line IN LISTS lines)
      math(EXPR number "${number} + 1")
      if(line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\"")
        set(header ${CMAKE_MATCH_1})
        math(EXPR checked "${checked} + 1")
        set(ok FALSE)
        foreach(pattern ${ALLOWED})
          if(header MATCHES "${pattern}")
            set(ok TRUE)
            break()
          endif()
        endforeach()
        if(NOT ok)
          message("${rel}:${number}: \"${header}\" is not a public header (allow-list: tests/packaging/public_includes.cmake)")
          math(EXPR bad "${bad} + 1")
        endif()
      endif()
    endforeach()
  endforeach()
endforeach()
if(checked EQUAL 0)
  message(FATAL_ERROR "public_includes: no #include found under ${DIRS}: wrong SOURCE?")
endif()
if(bad GREATER 0)
  message(FATAL_ERROR "public_includes: ${bad} internal include(s) in ${DIRS}")
endif()
message("public_includes: ${checked} includes in ${DIRS}, all public")
