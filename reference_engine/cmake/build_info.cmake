# Writes OUTPUT from TEMPLATE with which engine this build is (src/ratchet/core/build_info.hpp),
# at every build (cmake -P, from reference_engine/CMakeLists.txt). configure_file leaves an
# unchanged file alone, so nothing is recompiled unless the engine changed.
# Inputs: SOURCE_DIR (the repository), OUTPUT, TEMPLATE, BUILD_TYPE, COMPILER.

# The commit: git HEAD of SOURCE_DIR, "+modified" when tracked files differ from it.
# "unknown" without git, or when SOURCE_DIR is not a repository of its own (a tarball
# unpacked inside another repository must not take that repository's commit).
set(RATCHET_COMMIT "unknown")
find_program(RATCHET_GIT git)
if(RATCHET_GIT)
  execute_process(COMMAND ${RATCHET_GIT} -C ${SOURCE_DIR} rev-parse --show-toplevel
                  RESULT_VARIABLE rc OUTPUT_VARIABLE top OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  file(REAL_PATH "${SOURCE_DIR}" source_real)
  if(rc EQUAL 0)
    file(REAL_PATH "${top}" top_real)
  endif()
  if(rc EQUAL 0 AND top_real STREQUAL source_real)
    execute_process(COMMAND ${RATCHET_GIT} -C ${SOURCE_DIR} rev-parse --verify HEAD
                    RESULT_VARIABLE rc OUTPUT_VARIABLE head OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    if(rc EQUAL 0)
      set(RATCHET_COMMIT "${head}")
      # --no-optional-locks: a build must not take the index lock of a checkout in use.
      execute_process(COMMAND ${RATCHET_GIT} --no-optional-locks -C ${SOURCE_DIR} status --porcelain
                              --untracked-files=no
                      RESULT_VARIABLE rc OUTPUT_VARIABLE changes ERROR_QUIET)
      if(NOT rc EQUAL 0 OR NOT changes STREQUAL "")
        string(APPEND RATCHET_COMMIT "+modified")
      endif()
    endif()
  endif()
endif()

# The source hash: SHA-256 (first 16 hex digits) of the engine's sources and build
# settings, with or without git. It changes exactly when the code that makes the
# results can: the engine and program sources, the CMake files that set the compile
# flags, the build type and the compiler.
file(GLOB_RECURSE files RELATIVE ${SOURCE_DIR}
     ${SOURCE_DIR}/reference_engine/src/*.cpp ${SOURCE_DIR}/reference_engine/src/*.hpp
     ${SOURCE_DIR}/reference_engine/app/*.cpp ${SOURCE_DIR}/reference_engine/app/*.hpp)
list(APPEND files CMakeLists.txt reference_engine/CMakeLists.txt)
list(SORT files)
set(listing "build_type ${BUILD_TYPE}\ncompiler ${COMPILER}\n")
foreach(f IN LISTS files)
  file(SHA256 ${SOURCE_DIR}/${f} h)
  string(APPEND listing "${h} ${f}\n")
endforeach()
string(SHA256 RATCHET_SOURCE_HASH "${listing}")
string(SUBSTRING ${RATCHET_SOURCE_HASH} 0 16 RATCHET_SOURCE_HASH)

set(RATCHET_COMPILER "${COMPILER}")
configure_file(${TEMPLATE} ${OUTPUT} @ONLY)
