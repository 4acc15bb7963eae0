# The pbdsplat program as a user meets it: --help on every command, one JSON object with
# --json, and a clear one-line error with a non-zero exit on bad input.
# Run as: cmake -DPBDSPLAT=<exe> -DWORK_DIR=<dir> -P test_cli.cmake
file(MAKE_DIRECTORY "${WORK_DIR}")
set(failures 0)

function(expect name want_rc)
  execute_process(COMMAND ${PBDSPLAT} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  WORKING_DIRECTORY "${WORK_DIR}" TIMEOUT 300)
  if(NOT rc STREQUAL want_rc)
    message(SEND_ERROR "${name}: exit ${rc}, wanted ${want_rc}\nstdout: ${out}\nstderr: ${err}")
    math(EXPR f "${failures} + 1")
    set(failures ${f} PARENT_SCOPE)
  endif()
  set(last_out "${out}" PARENT_SCOPE)
  set(last_err "${err}" PARENT_SCOPE)
endfunction()

function(expect_contains name haystack needle)
  string(FIND "${haystack}" "${needle}" at)
  if(at EQUAL -1)
    message(SEND_ERROR "${name}: expected to find '${needle}' in:\n${haystack}")
    math(EXPR f "${failures} + 1")
    set(failures ${f} PARENT_SCOPE)
  endif()
endfunction()

# --help everywhere, on stdout, exit 0.
foreach(cmd "--help" "info;--help" "render;--help" "bench;--help" "bench;splat;--help")
  expect("help: ${cmd}" 0 ${cmd})
  expect_contains("help: ${cmd}" "${last_out}" "usage: pbdsplat")
endforeach()

# Usage errors: exit 2, a reason on stderr.
expect("no command" 2)
expect("unknown command" 2 frobnicate)
expect_contains("unknown command" "${last_err}" "unknown command 'frobnicate'")
expect("bad number" 2 render --width abc)
expect_contains("bad number" "${last_err}" "--width expects a whole number")
expect("out of range" 2 render --level 99)
expect_contains("out of range" "${last_err}" "--level must be between")
expect("unknown option" 2 info --colour)
expect_contains("unknown option" "${last_err}" "unknown option --colour")
expect("unknown suite" 2 bench warp)
expect("bad upload path" 2 render --upload teleport)

# info --json: one object with the documented keys.
expect("info --json" 0 info --json --validation)
foreach(key device driver api_version geometry_shader mesh_shader timestamps subgroup_size)
  string(JSON value ERROR_VARIABLE json_error GET "${last_out}" ${key})
  if(json_error)
    message(SEND_ERROR "info --json: key '${key}' missing: ${json_error}\n${last_out}")
    math(EXPR failures "${failures} + 1")
  endif()
endforeach()
string(JSON gs GET "${last_out}" geometry_shader)
string(JSON ms GET "${last_out}" mesh_shader)
message(STATUS "info: geometry_shader=${gs} mesh_shader=${ms}")
if(NOT ms)
  message(STATUS "mesh shaders: this device lacks VK_EXT_mesh_shader; the mesh-shader path would be skipped")
endif()

# render writes a PNG, creating its folder; a path it cannot write is an error naming it.
file(REMOVE_RECURSE "${WORK_DIR}/out")
expect("render" 0 render --width 96 --height 64 --level 2 --validation --out out/sub/frame.png)
if(NOT EXISTS "${WORK_DIR}/out/sub/frame.png")
  message(SEND_ERROR "render: out/sub/frame.png was not written")
  math(EXPR failures "${failures} + 1")
endif()
expect("render to an unwritable path" 1 render --width 32 --height 32 --level 0 --out /proc/pbdsplat/frame.png)
expect_contains("render to an unwritable path" "${last_err}" "/proc/pbdsplat")

# bench --json: one object with the medians.
expect("bench splat --json" 0 bench splat --count 500 --width 64 --height 64 --repeat 3 --warmup 1 --json --validation)
string(JSON draw ERROR_VARIABLE json_error GET "${last_out}" median_ms draw)
if(json_error)
  message(SEND_ERROR "bench splat --json: no median_ms.draw: ${json_error}\n${last_out}")
  math(EXPR failures "${failures} + 1")
endif()

if(failures GREATER 0)
  message(FATAL_ERROR "${failures} CLI check(s) failed")
endif()
