# The host-shader include compiles on its own with glslangValidator against an install tree, as a host
# compiles it: one -I (the tree's include/), `#include "manylights/manylights.glsl"` and nothing else
# from the module. A compute and a fragment shader, with the default bindings and with the set and first
# binding moved (ML_LIGHTS_SET / ML_LIGHTS_BINDING), each calling the include's functions.
#   cmake -DINCLUDE=<prefix>/include -DGLSLANG=<glslangValidator> -DOUT=<scratch dir> -P host_shader_include.cmake
# Run by ctest HostShaderIncludeStandalone (the staged tree) and ExampleHost_install (the installed one).
cmake_minimum_required(VERSION 3.25)
if(NOT INCLUDE OR NOT GLSLANG OR NOT OUT)
  message(FATAL_ERROR "host_shader_include.cmake: pass -DINCLUDE= -DGLSLANG= -DOUT=")
endif()
if(NOT EXISTS ${INCLUDE}/manylights/manylights.glsl)
  message(FATAL_ERROR "no manylights/manylights.glsl under ${INCLUDE}")
endif()
file(MAKE_DIRECTORY ${OUT})
set(body "
#include \"manylights/manylights.glsl\"
vec3 hostLight(uvec2 px, float d, vec3 N, vec3 albedo) {
    vec3 P = mlWorldPosition(px, d);
    vec3 V = normalize(mlCameraPosition() - P);
    vec3 sum = vec3(0.0);
    uvec2 range = mlClusterRange(px, d);
    for (uint i = 0; i < mlRangeCount(range); ++i) {
        GpuLight L = mlRangeLight(range, i);
        sum += shadeLight(L, P, normalize(N), V, albedo) * mlLightVisibility(L, P, N);
    }
    range = mlVisibleLights();
    if (mlRangeCount(range) > 0u) sum += mlRangeLight(range, 0u).colorSinOuter.xyz * 0.0;
    return sum;
}
")
set(header "#version 460\n#extension GL_GOOGLE_include_directive : require\n")
set(main_comp "layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 1, binding = 0, rgba16f) uniform writeonly image2D o;
void main() { imageStore(o, ivec2(gl_GlobalInvocationID.xy), vec4(hostLight(gl_GlobalInvocationID.xy, 0.5, vec3(0, 1, 0), vec3(0.5)), 1.0)); }
")
set(main_frag "layout(location = 0) out vec4 color;
void main() { color = vec4(hostLight(uvec2(gl_FragCoord.xy), gl_FragCoord.z, vec3(0, 1, 0), vec3(0.5)), 1.0); }
")
set(n 0)
foreach(moved OFF ON)
  set(defines "")
  if(moved)
    set(defines "#define ML_LIGHTS_SET 2\n#define ML_LIGHTS_BINDING 3\n")
  endif()
  foreach(stage comp frag)
    math(EXPR n "${n} + 1")
    set(src ${OUT}/host_${n}.${stage})
    file(WRITE ${src} "${header}${defines}${body}${main_${stage}}")
    execute_process(COMMAND ${GLSLANG} --target-env vulkan1.3 -I${INCLUDE} -o ${OUT}/host_${n}.spv ${src}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "the installed include does not compile (${stage}, -I${INCLUDE}):\n${out}\n${err}")
    endif()
  endforeach()
endforeach()
message("host_shader_include: ${n} host shaders compiled against ${INCLUDE}/manylights/manylights.glsl")
