# The Python bindings (python/): option KHZ_BUILD_PYTHON, on by default when Kilohertz is the
# top-level project and finds a Python 3 interpreter with NumPy, its headers and pybind11
# (Debian: python3-dev python3-numpy pybind11-dev).

# The first python3 on the PATH is not always the one with the system's NumPy (pyenv's shims or a
# virtual environment come first); take the first one that imports numpy, unless
# -DPython_EXECUTABLE=... chooses.
function(khz_python_imports_numpy result candidate)
  execute_process(COMMAND "${candidate}" -c "import numpy" RESULT_VARIABLE status OUTPUT_QUIET
                  ERROR_QUIET)
  if(NOT status EQUAL 0)
    set(${result} FALSE PARENT_SCOPE)
  endif()
endfunction()

set(khz_python_found FALSE)
if(PROJECT_IS_TOP_LEVEL OR KHZ_BUILD_PYTHON)
  find_program(Python_EXECUTABLE NAMES python3 python VALIDATOR khz_python_imports_numpy
               DOC "The Python interpreter the bindings are built for (one with NumPy)")
  if(Python_EXECUTABLE)
    find_package(Python 3.9 QUIET COMPONENTS Interpreter Development.Module NumPy)
    find_package(pybind11 2.10 QUIET CONFIG)
    if(Python_FOUND AND Python_NumPy_FOUND AND pybind11_FOUND)
      set(khz_python_found TRUE)
    endif()
  endif()
endif()

option(KHZ_BUILD_PYTHON "Build the kilohertz Python module (needs Python 3 with NumPy, pybind11)"
       ${khz_python_found})
if(KHZ_BUILD_PYTHON AND NOT khz_python_found)
  message(
    FATAL_ERROR
      "KHZ_BUILD_PYTHON is on but no Python 3 interpreter with NumPy, its development headers and "
      "pybind11 2.10+ were found (Debian: apt install python3-dev python3-numpy pybind11-dev; or "
      "give -DPython_EXECUTABLE=/path/to/python3)")
endif()
if(KHZ_BUILD_PYTHON)
  message(STATUS "Kilohertz Python module: for ${Python_EXECUTABLE} (${Python_VERSION}, "
                 "NumPy ${Python_NumPy_VERSION}, pybind11 ${pybind11_VERSION})")
  # Where `cmake --install` puts the package, relative to the prefix: lib/pythonX.Y/ and the
  # folder name this interpreter uses for a prefix's packages, so that installing to the
  # prefix it searches (/usr/local on Debian, whose Python reads dist-packages there) needs no
  # PYTHONPATH, and any other prefix is one PYTHONPATH=<prefix>/<this> away.
  execute_process(
    COMMAND "${Python_EXECUTABLE}" -c
            "import sysconfig; print(sysconfig.get_path('purelib').rstrip('/').split('/')[-1])"
    OUTPUT_VARIABLE khz_packages_folder OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT khz_packages_folder MATCHES "^(site|dist)-packages$")
    set(khz_packages_folder site-packages)
  endif()
  set(KHZ_PYTHON_INSTALL_DIR
      "lib/python${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}/${khz_packages_folder}"
      CACHE STRING "Install directory of the kilohertz Python package, relative to the prefix")
elseif(PROJECT_IS_TOP_LEVEL)
  message(STATUS "Kilohertz Python module: off (needs python3-dev python3-numpy pybind11-dev)")
endif()
