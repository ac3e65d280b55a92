# SPDX-License-Identifier: GPL-3.0-or-later
# One library target per engine layer (cpp/<layer>/CMakeLists.txt), and the include views that
# make the layering a build rule rather than a convention.
#
# Every engine include names its layer: "gl/texture3d.h", "fluid/grid.h". Instead of putting
# the whole cpp/ folder on the include path, each layer publishes only its own folder, through
# a view: <build>/layers/<layer>/<layer> is a link to cpp/<layer>, and <build>/layers/<layer>
# is the layer's include directory. A target sees its own view and those of the layers it links
# (usage requirements are transitive), so `#include "session/simulation.h"` from cpp/fluid fails
# to compile ("No such file or directory"): a lower layer cannot include a higher one.
#
# A layer may be a folder's sub-folder (the haptics parts: "haptics/devices"): its view is
# <build>/layers/haptics/devices, holding the link haptics/devices -> cpp/haptics/devices, so a
# target that sees one part does not see its sibling parts. The view links the whole folder, so
# a folder that is a layer of its own is never nested inside another layer's folder.

# hf_layer_view(<target> <folder> [PUBLIC|PRIVATE|INTERFACE])
# Gives <target> the view of cpp/<folder> (default PUBLIC; INTERFACE for header-only layers).
function(hf_layer_view target folder)
  set(scope PUBLIC)
  if(ARGC GREATER 2)
    set(scope ${ARGV2})
  endif()
  set(view ${PROJECT_BINARY_DIR}/layers/${folder})
  set(link ${view}/${folder})
  get_filename_component(link_parent ${link} DIRECTORY)
  file(MAKE_DIRECTORY ${link_parent})
  set(target_dir ${PROJECT_SOURCE_DIR}/cpp/${folder})
  if(IS_SYMLINK ${link})
    file(READ_SYMLINK ${link} current)
  endif()
  if(NOT current STREQUAL target_dir)  # new, or left by a source tree at another path
    file(REMOVE ${link})
    file(CREATE_LINK ${target_dir} ${link} SYMBOLIC)
  endif()
  target_include_directories(${target} ${scope} ${view})
endfunction()

# hf_layer_sources(<var> <folder>): the layer's .cpp files, globbed so that a new file in the
# folder joins its layer without a CMake edit (re-globbed at every build: CONFIGURE_DEPENDS).
function(hf_layer_sources var folder)
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/cpp/${folder}/*.cpp)
  set(${var} ${sources} PARENT_SCOPE)
endfunction()
