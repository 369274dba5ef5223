# Parts that are not the shards of one bake are refused by `manylights merge` with exit status 2 and one
# line on stderr naming the parts or lights: missing, doubled, other method / resolution / scene /
# scene geometry / renderer / selection, damaged or truncated, a whole bake file; and inspect / verify
# refuse a part with one line.
#   cmake -DEXE=path/to/manylights -DOUT=dir -DSCENE=tests/cli/point_light.gltf -P shard_reject.cmake
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(base --method mh --res 64 --lights 0-4,240 --renderer cpu --quiet)

function(bake name)
  execute_process(COMMAND ${EXE} bake ${ARGN} --out ${OUT}/${name} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "bake ${ARGN} exited ${rc}: ${err}")
  endif()
endfunction()
# expect(REGEX cmd args...): exit 2 and stderr is one line "manylights <cmd>: " matching REGEX.
function(expect regex cmd)
  execute_process(COMMAND ${EXE} ${cmd} ${ARGN} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  string(STRIP "${err}" err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "^manylights ${cmd}: [^\n]*${regex}[^\n]*$")
    message(FATAL_ERROR "'${cmd} ${ARGN}': exit ${rc} (expected 2), stderr '${err}' (expected one line matching '${regex}')")
  endif()
endfunction()
# flip(src dst offset): a copy of src with the byte at offset replaced by its complement-ish (0x5a or 0xa5).
function(flip src dst offset)
  file(COPY_FILE ${src} ${dst})
  file(READ ${src} byte OFFSET ${offset} LIMIT 1 HEX)
  set(new "\\132") # 0x5a
  if(byte STREQUAL "5a")
    set(new "\\245")
  endif()
  execute_process(COMMAND sh -c "printf '${new}' | dd of='${dst}' bs=1 seek=${offset} conv=notrunc status=none" RESULT_VARIABLE rc)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${src} ${dst} RESULT_VARIABLE differs)
  if(NOT rc EQUAL 0 OR differs EQUAL 0)
    message(FATAL_ERROR "could not damage ${dst} at byte ${offset}")
  endif()
endfunction()

bake(p0.mlbp ${base} --shard 0/2)
bake(p1.mlbp ${base} --shard 1/2)
execute_process(COMMAND ${EXE} merge ${OUT}/p0.mlbp ${OUT}/p1.mlbp --out ${OUT}/good.mlbk RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "merging the good parts exited ${rc}: ${err}")
endif()

# Missing and doubled: the lights and files are named.
expect("lights? [0-9, ]+ of the selection in no part \\(missing shard 0/2\\)" merge ${OUT}/p1.mlbp --out ${OUT}/x.mlbk)
expect("lights? [0-9, ]+ baked twice: in ${OUT}/p0.mlbp \\(shard 0/2\\) and ${OUT}/p0.mlbp \\(shard 0/2\\)"
       merge ${OUT}/p0.mlbp ${OUT}/p1.mlbp ${OUT}/p0.mlbp --out ${OUT}/x.mlbk)
if(EXISTS ${OUT}/x.mlbk)
  message(FATAL_ERROR "a refused merge wrote its output")
endif()

# Mismatched settings: shard 1 of another bake.
bake(sm.mlbp --method sm --res 64 --lights 0-4,240 --renderer cpu --quiet --shard 1/2)
expect("${OUT}/p0.mlbp and ${OUT}/sm.mlbp are not parts of one bake: method mh vs sm" merge ${OUT}/p0.mlbp ${OUT}/sm.mlbp --out ${OUT}/x.mlbk)
bake(res.mlbp --method mh --res 32 --lights 0-4,240 --renderer cpu --quiet --shard 1/2)
expect("resolution 64 vs 32" merge ${OUT}/p0.mlbp ${OUT}/res.mlbp --out ${OUT}/x.mlbk)
bake(scene.mlbp ${base} --scene-lights 250 --shard 1/2)
expect("scene night-city \\(256 lights, seed 1\\) vs night-city \\(250 lights, seed 1\\)" merge ${OUT}/p0.mlbp ${OUT}/scene.mlbp --out ${OUT}/x.mlbk)
bake(gpu.mlbp --method mh --res 64 --lights 0-4,240 --renderer gpu --quiet --shard 1/2)
expect("renderer cpu vs gpu" merge ${OUT}/p0.mlbp ${OUT}/gpu.mlbp --out ${OUT}/x.mlbk)
bake(sel.mlbp --method mh --res 64 --lights 0-5,240 --renderer cpu --quiet --shard 1/2)
expect("light selection" merge ${OUT}/p0.mlbp ${OUT}/sel.mlbp --out ${OUT}/x.mlbk)
bake(n3.mlbp ${base} --shard 1/3)
expect("shard count 2 vs 3" merge ${OUT}/p0.mlbp ${OUT}/n3.mlbp --out ${OUT}/x.mlbk)
# The same scene path with other contents between the shards: only the fingerprint sees it.
file(COPY_FILE ${SCENE} ${OUT}/scene.gltf)
set(gltf --method mh --res 64 --lights all --scene ${OUT}/scene.gltf --scene-lights 4 --renderer cpu --quiet)
bake(g0.mlbp ${gltf} --shard 0/2)
file(READ ${OUT}/scene.gltf text)
string(REPLACE "2.5," "2.75," moved "${text}")
if(moved STREQUAL text)
  message(FATAL_ERROR "the test scene has no light at x = 2.5 to move")
endif()
file(WRITE ${OUT}/scene.gltf "${moved}")
bake(g1.mlbp ${gltf} --shard 1/2)
expect("scene fingerprint" merge ${OUT}/g0.mlbp ${OUT}/g1.mlbp --out ${OUT}/x.mlbk)

# Damaged parts: header, inner data, truncated; and not a part at all.
file(SIZE ${OUT}/p1.mlbp size)
flip(${OUT}/p1.mlbp ${OUT}/head.mlbp 40)
expect("${OUT}/head.mlbp: header: checksum mismatch" merge ${OUT}/p0.mlbp ${OUT}/head.mlbp --out ${OUT}/x.mlbk)
math(EXPR last "${size} - 7")
flip(${OUT}/p1.mlbp ${OUT}/data.mlbp ${last})
expect("${OUT}/data.mlbp: inner bake file: record [0-9]+: data checksum mismatch" merge ${OUT}/p0.mlbp ${OUT}/data.mlbp --out ${OUT}/x.mlbk)
math(EXPR cut "${size} - 4")
execute_process(COMMAND head -c ${cut} ${OUT}/p1.mlbp OUTPUT_FILE ${OUT}/cut.mlbp)
expect("${OUT}/cut.mlbp: file should be ${size} bytes but is ${cut}" merge ${OUT}/p0.mlbp ${OUT}/cut.mlbp --out ${OUT}/x.mlbk)
expect("${OUT}/good.mlbk: a whole bake file, not a part" merge ${OUT}/p0.mlbp ${OUT}/good.mlbk --out ${OUT}/x.mlbk)
expect("${OUT}/missing.mlbp: no such file" merge ${OUT}/p0.mlbp ${OUT}/missing.mlbp --out ${OUT}/x.mlbk)
expect("no PART files" merge --out ${OUT}/x.mlbk)
expect("--out: required" merge ${OUT}/p0.mlbp ${OUT}/p1.mlbp)
# A part is not a bake file for inspect and verify.
expect("${OUT}/p0.mlbp: one part of a sharded bake .*manylights merge" inspect ${OUT}/p0.mlbp)
expect("${OUT}/p0.mlbp: one part of a sharded bake .*manylights merge" verify ${OUT}/p0.mlbp)
# And bake rejects a malformed --shard.
expect("--shard: '2/2' is not I/N" bake ${base} --shard 2/2 --out ${OUT}/x.mlbp)
if(EXISTS ${OUT}/x.mlbk)
  message(FATAL_ERROR "a refused merge wrote its output")
endif()
message(STATUS "all bad parts refused")
