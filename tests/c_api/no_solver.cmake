# ctest c_api_no_solver: libmassid_c holds no Ceres code and needs none of its
# libraries (glog, cholmod, lapack...): loading a model and predicting does
# not reach the physical fit (src/identify/physical.cpp), its only user; the
# C library links the parts core, io and live only (capi/CMakeLists.txt).
# cmake -DLIBRARY=libmassid_c.so -DNM=nm -DREADELF=readelf -P this
execute_process(COMMAND ${NM} -C ${LIBRARY} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} -C ${LIBRARY} failed (${rc})")
endif()
# (string(FIND), not a regular expression over every line: nm's output of a
# library that did pull Ceres in is megabytes.)
string(FIND "${symbols}" "ceres::" at)
if(NOT at EQUAL -1)
  string(SUBSTRING "${symbols}" ${at} 200 first)
  string(REGEX REPLACE "\n.*" "" first "${first}")
  message(FATAL_ERROR "${LIBRARY} holds Ceres symbols, e.g. ${first}: the C interface "
                      "reaches the identify part (it links massid_part_live only)")
endif()
execute_process(COMMAND ${READELF} -d ${LIBRARY} OUTPUT_VARIABLE dynamic RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${READELF} -d ${LIBRARY} failed (${rc})")
endif()
foreach(lib glog cholmod cxsparse lapack blas ceres)
  if(dynamic MATCHES "NEEDED[^\n]*lib${lib}")
    message(FATAL_ERROR "${LIBRARY} needs lib${lib}, a dependency of the physical fit only")
  endif()
endforeach()
message(STATUS "${LIBRARY}: no Ceres code, no solver library needed")
