# Runs one command and checks its exit status and output, for command-line
# tests that plain ctest properties cannot express (exit 2 vs 1, stderr
# present AND absent). Usage:
#   cmake "-DCMD=prog|arg|..." -DRC=N [-DOUT_RE=...] [-DERR_RE=...] [-DERR_NOT_RE=...]
#         [-DFILE=path -DFILE_RE=...] [-DDATA=dir] [-DNEED=rel/path] -P expect_run.cmake
# CMD's arguments are separated by '|'; '%DATA%' in them stands for the data
# root: $TRISTEREO_DATA_DIR, else DATA (the ../shared/data the build was
# configured with), as in tests/support/data.cpp.
# NEED: files under the data root the command needs ('|'-separated); when it is missing the
# test fails naming it, or prints "SKIP: no ..." (the test's
# SKIP_REGULAR_EXPRESSION) under TRISTEREO_ALLOW_MISSING_DATA=1 (the rule of
# tests/support/data.hpp).
cmake_minimum_required(VERSION 3.16)
if(NOT "$ENV{TRISTEREO_DATA_DIR}" STREQUAL "")
  set(DATA "$ENV{TRISTEREO_DATA_DIR}")
endif()
string(REPLACE "%DATA%" "${DATA}" CMD "${CMD}")
string(REPLACE "|" ";" CMD "${CMD}")
if(DEFINED NEED)
  string(REPLACE "|" ";" NEED "${NEED}")
  foreach(need IN LISTS NEED)
    if(NOT EXISTS "${DATA}/${need}")
      if("$ENV{TRISTEREO_ALLOW_MISSING_DATA}" STREQUAL "1")
        message("SKIP: no ${DATA}/${need} (TRISTEREO_ALLOW_MISSING_DATA=1)")
        return()
      endif()
      message(FATAL_ERROR "stereo data not found: ${DATA}/${need} (put ../shared beside the project, "
                          "or set TRISTEREO_ALLOW_MISSING_DATA=1 to skip the tests that need it)")
    endif()
  endforeach()
endif()
execute_process(COMMAND ${CMD} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("exit ${rc}\n--- stdout\n${out}--- stderr\n${err}---")
if(NOT "${rc}" STREQUAL "${RC}")
  message(FATAL_ERROR "expected exit ${RC}, got ${rc}")
endif()
if(DEFINED OUT_RE AND NOT out MATCHES "${OUT_RE}")
  message(FATAL_ERROR "stdout does not match '${OUT_RE}'")
endif()
if(DEFINED ERR_RE AND NOT err MATCHES "${ERR_RE}")
  message(FATAL_ERROR "stderr does not match '${ERR_RE}'")
endif()
if(DEFINED ERR_NOT_RE AND err MATCHES "${ERR_NOT_RE}")
  message(FATAL_ERROR "stderr matches '${ERR_NOT_RE}', which it must not")
endif()
if(DEFINED FILE)
  if(NOT EXISTS "${FILE}")
    message(FATAL_ERROR "${FILE} was not written")
  endif()
  file(READ "${FILE}" text)
  if(DEFINED FILE_RE AND NOT text MATCHES "${FILE_RE}")
    message(FATAL_ERROR "${FILE} does not match '${FILE_RE}'")
  endif()
endif()
