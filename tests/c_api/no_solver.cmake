# ctest c_api_no_solver: libmassid_c holds no Ceres code and needs none of its
# libraries (glog, cholmod, lapack...): loading a model and predicting does
# not reach the physical fit (src/physical.cpp), its only user.
# cmake -DLIBRARY=libmassid_c.so -DNM=nm -DREADELF=readelf -P this
execute_process(COMMAND ${NM} -C ${LIBRARY} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} -C ${LIBRARY} failed (${rc})")
endif()
string(REGEX MATCHALL "[^\n]*ceres::[^\n]*" ceres "${symbols}")
list(LENGTH ceres n)
if(n GREATER 0)
  list(GET ceres 0 first)
  message(FATAL_ERROR "${LIBRARY} holds ${n} Ceres symbols, e.g. ${first}: something the C "
                      "interface reaches is in a file with the physical fit")
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
