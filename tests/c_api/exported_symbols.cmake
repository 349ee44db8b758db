# ctest c_api_symbols: libmassid_c exports exactly the functions massid.h
# declares. cmake -DLIBRARY=libmassid_c.so -DNM=nm -DHEADER=include/massid.h -P this
execute_process(COMMAND ${NM} -D --defined-only ${LIBRARY} OUTPUT_VARIABLE nm_out
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} -D --defined-only ${LIBRARY} failed (${rc})")
endif()
# Lines "ADDRESS TYPE NAME"; code and data symbols (the version node, type A, is not one).
string(REGEX MATCHALL "[0-9a-fA-F]+ [TtDdBbRrWwVv] [^\n]+" lines "${nm_out}")
set(exported "")
foreach(line IN LISTS lines)
  string(REGEX REPLACE "^[0-9a-fA-F]+ . ([^@\n]+).*$" "\\1" name "${line}")
  list(APPEND exported ${name})
endforeach()
list(SORT exported)

file(READ ${HEADER} header)
string(REGEX MATCHALL "MASSID_C_API [^;(]*[ *](massid_[a-z_]+)\\(" decls "${header}")
set(declared "")
foreach(d IN LISTS decls)
  string(REGEX REPLACE ".*[ *](massid_[a-z_]+)\\($" "\\1" name "${d}")
  list(APPEND declared ${name})
endforeach()
list(SORT declared)

list(LENGTH declared n_declared)
if(n_declared LESS 10)
  message(FATAL_ERROR "found only ${n_declared} declarations in ${HEADER}: ${declared}")
endif()
if(NOT exported STREQUAL declared)
  set(extra ${exported})
  list(REMOVE_ITEM extra ${declared})
  set(missing ${declared})
  list(REMOVE_ITEM missing ${exported})
  message(FATAL_ERROR "${LIBRARY} exports what massid.h does not declare: [${extra}]; "
                      "massid.h declares what it does not export: [${missing}]")
endif()
message(STATUS "${LIBRARY}: ${n_declared} symbols, all declared in massid.h: ${exported}")
