# Chooses the Python interpreter of the bindings (python/) before pybind11 looks for one: the
# one given as Python3_EXECUTABLE, else the first of /usr/bin/python3 (Debian's, which sees
# Debian's python3-numpy and python3-dask) and the python3 on PATH that imports numpy, else
# /usr/bin/python3 when it exists. Sets FREESPACE_PYTHON_HAS_NUMPY.
if(NOT Python3_EXECUTABLE)
  find_program(FREESPACE_PATH_PYTHON3 python3)
  set(candidates "")
  if(EXISTS /usr/bin/python3)
    list(APPEND candidates /usr/bin/python3)
  endif()
  if(FREESPACE_PATH_PYTHON3)
    list(APPEND candidates ${FREESPACE_PATH_PYTHON3})
  endif()
  foreach(candidate IN LISTS candidates)
    execute_process(COMMAND ${candidate} -c "import numpy" RESULT_VARIABLE rc
                    OUTPUT_QUIET ERROR_QUIET)
    if(rc EQUAL 0)
      set(Python3_EXECUTABLE ${candidate} CACHE FILEPATH "Python of the freespace module")
      break()
    endif()
  endforeach()
  if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python of the freespace module")
  endif()
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module)
set(FREESPACE_PYTHON_HAS_NUMPY OFF)
if(Python3_FOUND)
  execute_process(COMMAND ${Python3_EXECUTABLE} -c "import numpy" RESULT_VARIABLE rc
                  OUTPUT_QUIET ERROR_QUIET)
  if(rc EQUAL 0)
    set(FREESPACE_PYTHON_HAS_NUMPY ON)
  endif()
endif()
