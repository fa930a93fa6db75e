# vpm_require_package(<Name> <debian-package> [find_package arguments...])
# find_package(<Name> ... QUIET); when nothing is found, stops the configure with one message that
# names the Debian 12 package to install (the dependencies come from Debian, for the CMake build
# and for `pip install .` alike). A macro, so that the package's variables reach the caller.
macro(vpm_require_package _vpm_name _vpm_debian)
  find_package(${_vpm_name} ${ARGN} QUIET)
  if(NOT ${_vpm_name}_FOUND)
    message(FATAL_ERROR "vpm needs ${_vpm_name}, which Debian 12 packages: apt-get install ${_vpm_debian}\n"
                        "(bash scripts/install-deps.sh installs every dependency; "
                        "cmake --debug-find-pkg=${_vpm_name} shows where CMake looked)")
  endif()
endmacro()
