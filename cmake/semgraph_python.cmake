# Finds the Python interpreter for the bindings (python/) and sets SEMGRAPH_PYTHON_DEFAULT, the
# default of the SEMGRAPH_BUILD_PYTHON option: ON when semgraph is the top-level project, the
# build is not instrumented with a sanitizer (an instrumented module cannot be loaded into an
# uninstrumented interpreter), and an interpreter with numpy and its C headers plus pybind11 are
# found.
#
# One interpreter builds, installs and tests the module. Unless Python3_EXECUTABLE is given, it is
# the first `python3` on PATH, then /usr/bin/python3, that can import numpy and has Python.h
# (the first python3 on PATH is not always the system's, e.g. a pyenv shim without numpy).
set(SEMGRAPH_PYTHON_DEFAULT OFF)
if(NOT PROJECT_IS_TOP_LEVEL OR CMAKE_CXX_FLAGS MATCHES "-fsanitize")
  return()
endif()

if(NOT DEFINED Python3_EXECUTABLE)
  string(REPLACE ":" ";" _semgraph_path "$ENV{PATH}")
  foreach(_dir IN LISTS _semgraph_path ITEMS /usr/bin)
    if(NOT EXISTS "${_dir}/python3")
      continue()
    endif()
    execute_process(
      COMMAND "${_dir}/python3" -c
              "import numpy, os, sys, sysconfig; sys.exit(not os.path.exists(os.path.join(sysconfig.get_paths()['include'], 'Python.h')))"
      RESULT_VARIABLE _semgraph_rc OUTPUT_QUIET ERROR_QUIET)
    if(_semgraph_rc EQUAL 0)
      set(Python3_EXECUTABLE "${_dir}/python3" CACHE FILEPATH
          "The Python interpreter semgraph's bindings are built for and tested with")
      break()
    endif()
  endforeach()
endif()

find_package(Python3 3.8 QUIET COMPONENTS Interpreter Development.Module)
if(Python3_FOUND)
  find_package(pybind11 2.6 CONFIG QUIET)
endif()
if(Python3_FOUND AND pybind11_FOUND)
  set(SEMGRAPH_PYTHON_DEFAULT ON)
endif()
