# Finds the Python the module is built for, without letting a broken `python3` on PATH (a pyenv
# shim naming a version that is not installed, say) stop the configure: pybind11's own search
# fails hard there. Sets RANGEFUSE_PYTHON_PACKAGES to the interpreter's package folder under a
# prefix (Debian: lib/python3.11/dist-packages), and PYTHON_EXECUTABLE for pybind11.

# True in `out` when `python` runs and has the headers a module is compiled against.
function(rangefuse_python_usable python out)
  execute_process(
    COMMAND ${python} -c "import sys, sysconfig, os.path; \
assert sys.version_info[0] == 3; \
assert os.path.exists(os.path.join(sysconfig.get_paths()['include'], 'Python.h'))"
    RESULT_VARIABLE failed OUTPUT_QUIET ERROR_QUIET)
  if(failed)
    set(${out} FALSE PARENT_SCOPE)
  else()
    set(${out} TRUE PARENT_SCOPE)
  endif()
endfunction()

# Where the interpreter installs packages, relative to a prefix. Debian's default scheme puts
# them under local/ because it expects the prefix /usr; without it the path is what Debian's
# Python searches under any other prefix (/usr/local/lib/python3.11/dist-packages).
function(rangefuse_python_packages python out)
  execute_process(
    COMMAND ${python} -c "import sysconfig; \
p = sysconfig.get_path('platlib', vars={'platbase': '@P@', 'base': '@P@'}); \
p = p[len('@P@/'):]; \
print(p[len('local/'):] if p.startswith('local/') else p, end='')"
    OUTPUT_VARIABLE packages RESULT_VARIABLE failed ERROR_QUIET)
  if(failed OR packages STREQUAL "")
    set(packages lib/python3/dist-packages)
  endif()
  set(${out} ${packages} PARENT_SCOPE)
endfunction()

# Sets `enabled` (a variable holding ON) to OFF, with one status line, when no module can be built.
macro(rangefuse_python_for_module enabled)
  if(NOT PYTHON_EXECUTABLE)
    # Not find_package(Python3): it would switch pybind11 to a mode that needs more of Python.
    find_program(path_python3 NAMES python3 NO_CACHE)
    foreach(candidate ${path_python3} /usr/bin/python3)
      rangefuse_python_usable(${candidate} usable)
      if(usable)
        set(PYTHON_EXECUTABLE ${candidate} CACHE FILEPATH "The Python the module is built for")
        break()
      endif()
    endforeach()
  endif()
  if(PYTHON_EXECUTABLE)
    rangefuse_python_usable(${PYTHON_EXECUTABLE} usable)
  else()
    set(usable FALSE)
  endif()
  if(NOT usable)
    message(STATUS "Python module skipped: no Python 3 with its headers runs "
                   "(-DPYTHON_EXECUTABLE=... to name one; Debian: python3-dev)")
    set(${enabled} OFF)
  else()
    find_package(pybind11 CONFIG QUIET)
    if(NOT pybind11_FOUND)
      message(STATUS "Python module skipped: pybind11 not found (Debian: pybind11-dev)")
      set(${enabled} OFF)
    else()
      rangefuse_python_packages(${PYTHON_EXECUTABLE} RANGEFUSE_PYTHON_PACKAGES)
    endif()
  endif()
endmacro()
