# SPDX-License-Identifier: GPL-3.0-or-later
# Wheel-only build rules, included from the top CMakeLists.txt. They act only when
# scikit-build-core drives the build (pyproject.toml; it sets SKBUILD), and install into the
# component `hf_wheel`, the only one pyproject.toml puts into the wheel, so the wheel holds
# exactly the package and its native module whatever other install() rules the project has.
# The package's pure-Python files come from `wheel.packages` (python/hapticfluid), so here
# only `_core` is installed, beside them. Vendoring of OpenVDB, TBB etc. is auditwheel's job
# afterwards (scripts/build_wheel.sh), not CMake's.
if(NOT SKBUILD)
  return()
endif()

# One version: pyproject.toml reads it from project(VERSION) above; refuse a wheel whose
# metadata or package disagrees with it (python/hapticfluid/__init__.py states it too).
if(NOT SKBUILD_PROJECT_VERSION STREQUAL PROJECT_VERSION)
  message(FATAL_ERROR "wheel version ${SKBUILD_PROJECT_VERSION} (pyproject.toml) is not the project's "
                      "version ${PROJECT_VERSION} (CMakeLists.txt project()): fix pyproject's regex")
endif()
file(STRINGS ${CMAKE_SOURCE_DIR}/python/hapticfluid/__init__.py HF_PY_VERSION_LINE
     REGEX "^__version__ = \"[^\"]*\"$")
if(NOT HF_PY_VERSION_LINE STREQUAL "__version__ = \"${PROJECT_VERSION}\"")
  message(FATAL_ERROR "python/hapticfluid/__init__.py says '${HF_PY_VERSION_LINE}', the project's "
                      "version is ${PROJECT_VERSION} (CMakeLists.txt project()): make them equal")
endif()

install(TARGETS _core LIBRARY DESTINATION hapticfluid COMPONENT hf_wheel)
