# ctest python_install: `cmake --install` into a staging root (DESTDIR), then
# the staged package imports and runs without the build tree, and the staged
# CLI reports its version. -DBUILD=<build dir> -DPYTHON=<interpreter> -DSITE=<site-packages>
set(stage ${BUILD}/install_check)
file(REMOVE_RECURSE ${stage})
execute_process(COMMAND ${CMAKE_COMMAND} -E env DESTDIR=${stage} ${CMAKE_COMMAND} --install ${BUILD}
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
foreach(f __init__.py report.py _massid.pyi py.typed)
  if(NOT EXISTS ${stage}${SITE}/massid/${f})
    message(FATAL_ERROR "not installed: ${SITE}/massid/${f}")
  endif()
endforeach()
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${stage}${SITE}
          ${PYTHON} -c "import massid, pathlib; assert pathlib.Path(massid.__file__).is_relative_to('${stage}'), massid.__file__; m = massid.load_model_string('<robot name=\"r\"><link name=\"a\"><inertial><mass value=\"2\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link></robot>'); assert m.nominal_total_mass == 2.0; print(massid.__version__)"
  WORKING_DIRECTORY ${stage}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the installed package does not import: ${err}")
endif()
message(STATUS "installed massid ${out}")
