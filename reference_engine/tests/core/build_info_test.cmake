# The engine's commit and source hash (reference_engine/cmake/build_info.cmake) for
# sources that are not a git checkout of their own, as from a release tarball: a copy
# of the engine's sources alone, and the same copy inside another git repository
# (which must not lend it its commit). Both give commit "unknown" and the source hash
# of the build that runs this test: the hash needs no git. Run by CTest (cmake -P) with
# SOURCE_DIR, WORK_DIR, BUILD_INFO (the build's generated build_info.cpp), BUILD_TYPE
# and COMPILER.
function(expect_build_info dir what)
  execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${dir} -DOUTPUT=${WORK_DIR}/out.cpp
                          -DTEMPLATE=${SOURCE_DIR}/reference_engine/cmake/build_info.cpp.in
                          -DBUILD_TYPE=${BUILD_TYPE} "-DCOMPILER=${COMPILER}"
                          -P ${SOURCE_DIR}/reference_engine/cmake/build_info.cmake
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what}: build_info.cmake failed: ${err}")
  endif()
  file(READ ${WORK_DIR}/out.cpp got)
  if(NOT got MATCHES "engine_commit\\(\\) { return \"unknown\"; }")
    message(FATAL_ERROR "${what}: expected commit \"unknown\", got:\n${got}")
  endif()
  file(READ ${BUILD_INFO} built)
  string(REGEX MATCH "engine_source_hash\\(\\) { return \"([0-9a-f]+)\"; }" _ "${built}")
  set(want ${CMAKE_MATCH_1})
  string(REGEX MATCH "engine_source_hash\\(\\) { return \"([0-9a-f]+)\"; }" _ "${got}")
  set(hash ${CMAKE_MATCH_1})  # before if(MATCHES) sets CMAKE_MATCH_1 again
  if(NOT want MATCHES "^[0-9a-f]+$" OR NOT hash STREQUAL want)
    message(FATAL_ERROR "${what}: expected the build's source hash ${want}, got ${hash}")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(copy ${WORK_DIR}/outer/ratchet-0.1.0)
file(MAKE_DIRECTORY ${copy}/reference_engine)
file(COPY ${SOURCE_DIR}/CMakeLists.txt DESTINATION ${copy})
file(COPY ${SOURCE_DIR}/reference_engine/CMakeLists.txt ${SOURCE_DIR}/reference_engine/src
          ${SOURCE_DIR}/reference_engine/app DESTINATION ${copy}/reference_engine)
expect_build_info(${copy} "a copy without git")

find_program(GIT git)
if(GIT)
  execute_process(COMMAND ${GIT} init -q ${WORK_DIR}/outer RESULT_VARIABLE rc)
  if(rc EQUAL 0)
    expect_build_info(${copy} "a copy inside another repository")
  endif()
endif()
file(REMOVE_RECURSE ${WORK_DIR})
