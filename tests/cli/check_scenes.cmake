# Label `scenes`: a scene runs through `pbdsplat check` for the frames its [expect] table names
# and is held to that table's bounds (docs/scene-format.md): the check exits 1 naming each claim
# that does not hold. Scenes on models from ../shared/models are skipped (ctest shows a skip)
# where those models are not on the search path; any other missing model fails.
# Args: -DPBDSPLAT=<exe> -DSCENES_DIR=<scenes/> -DSCENE=<stem>
execute_process(COMMAND ${PBDSPLAT} check ${SCENES_DIR}/${SCENE}.toml --every 10 --width 240 --height 135 --validation --json
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
# Only the shared test models (../shared/models, never in the repository) may be missing; a scene
# that names a model wrongly fails.
if(NOT rc EQUAL 0 AND err MATCHES "(stanford-bunny|teapot|suzanne|fandisk)\\.obj: no such file, and not a procedural mesh")
  message("SKIPPED: ${SCENE}: its shared test model is not on the model search path: ${err}")
  return()
endif()
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${SCENE}: pbdsplat check failed (${rc}): ${err}")
endif()
# A scene without claims would pass whatever it showed.
string(JSON claims LENGTH "${out}" expect)
if(claims EQUAL 0)
  message(FATAL_ERROR "${SCENE}: the scene has no [expect] bounds: state what it shows (docs/scene-format.md)")
endif()
math(EXPR last "${claims} - 1")
foreach(i RANGE ${last})
  string(JSON figure GET "${out}" expect ${i} figure)
  string(JSON bound GET "${out}" expect ${i} bound)
  string(JSON limit GET "${out}" expect ${i} limit)
  string(JSON value GET "${out}" expect ${i} value)
  message(STATUS "${SCENE}: ${figure} = ${value} (${bound} ${limit})")
endforeach()
