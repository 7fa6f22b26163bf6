# Checks a `tristereo match --stats` file: valid JSON with the per-stage times
# and run_ms, the one-shot run's phases (docs/performance.md, "One-shot
# match"): each measured (>= 0, not the -1 of "not measured"), reading the
# inputs longer than nothing, and the frame as the caller saw it no shorter
# than the pipeline's own total.
# Usage: cmake -DFILE=stats.json -P check_stats_json.cmake
cmake_minimum_required(VERSION 3.19)  # string(JSON)
file(READ "${FILE}" json)
string(JSON total GET "${json}" ms total)
foreach(field read_inputs configure frame checks)
  string(JSON v ERROR_VARIABLE err GET "${json}" run_ms ${field})
  if(err)
    message(FATAL_ERROR "${FILE}: no run_ms.${field} (${err})")
  endif()
  if(v LESS 0)
    message(FATAL_ERROR "${FILE}: run_ms.${field} = ${v}: not measured")
  endif()
  set(run_${field} "${v}")
endforeach()
# if(LESS) compares the decimal strings as numbers.
if(NOT run_read_inputs GREATER 0)
  message(FATAL_ERROR "${FILE}: run_ms.read_inputs = ${run_read_inputs}")
endif()
if(run_frame LESS total)
  message(FATAL_ERROR "${FILE}: run_ms.frame ${run_frame} < ms.total ${total}")
endif()
message("ok: ms.total ${total}; run_ms read_inputs ${run_read_inputs}, configure ${run_configure}, "
        "frame ${run_frame}, checks ${run_checks}")
