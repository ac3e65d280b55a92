// SPDX-License-Identifier: GPL-3.0-or-later
#include "emitter/mesh_source.h"

#include <string>
#include <utility>

#include "common/error.h"
#include "common/format.h"
#include "fluid/validate.h"

namespace hf::emitter {

void validateSourcePose(const obstacle::MeshExtent& extent, const glm::mat4& transform, const fluid::Grid& g) {
  obstacle::validateTransform(transform);
  // Sub-columns are kSourceSubsamples times denser than cell columns along x and y.
  const double visits = obstacle::columnVisitBound(extent, transform, g.cell_size_m / kSourceSubsamples);
  if (!(visits <= obstacle::kMaxColumnVisits)) {
    throw InvalidArgument("the posed smoke source mesh's triangles could cover up to " + num(visits) +
                          " sub-columns per step (limit " + num(obstacle::kMaxColumnVisits) +
                          "); split its large triangles, scale it down or use a coarser grid");
  }
  const obstacle::WorldBox box = obstacle::worldBox(extent, transform);
  const glm::vec3 lo = g.origin_m, hi = g.origin_m + g.sizeM();
  if (glm::any(glm::greaterThanEqual(box.lo, hi)) || glm::any(glm::lessThanEqual(box.hi, lo))) {
    throw InvalidArgument("move the smoke source into the domain: the posed mesh (bounds " + vecText(box.lo) +
                          " .. " + vecText(box.hi) + " m) lies entirely outside the domain " + vecText(lo) +
                          " .. " + vecText(hi) + " m");
  }
  const glm::vec3 size = g.sizeM();
  if (glm::any(glm::lessThan(box.lo, lo - size)) || glm::any(glm::greaterThan(box.hi, hi + size))) {
    throw InvalidArgument("cut or scale down the smoke source mesh: its posed bounds " + vecText(box.lo) + " .. " +
                          vecText(box.hi) + " m reach more than one domain size past the domain " + vecText(lo) +
                          " .. " + vecText(hi) + " m");
  }
}

MeshSource makeMeshSource(obstacle::TriangleMesh mesh, const glm::mat4& transform, float density,
                          float temperature_k, fluid::SourceEmission emission, const fluid::Grid& grid) {
  fluid::validateSourceValues(density, temperature_k, emission);
  MeshSource s;
  try {
    obstacle::validateMesh(mesh);
    s.extent = obstacle::meshExtent(mesh);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(std::string("smoke source mesh: ") + e.what());
  }
  validateSourcePose(s.extent, transform, grid);
  s.mesh = std::make_shared<const obstacle::TriangleMesh>(std::move(mesh));
  s.transform = transform;
  s.density = density;
  s.temperature_k = temperature_k;
  s.emission = emission;
  return s;
}

}  // namespace hf::emitter
