// SPDX-License-Identifier: GPL-3.0-or-later
#include "cpu/kernels/kernel_list.h"

namespace hf::cpu {

const KernelRegistry& kernelRegistry() {
  static const KernelRegistry registry = [] {
    KernelRegistry r;
    kernels::addAdvect(r);
    kernels::addApplyForces(r);
    kernels::addBinaryFractions(r);
    kernels::addCellForces(r);
    kernels::addClassify(r);
    kernels::addDivergence(r);
    kernels::addEmitCoverage(r);
    kernels::addEmitMeshCoverage(r);
    kernels::addEmitMeshCrossings(r);
    kernels::addEnforceBoundaries(r);
    kernels::addForceFaces(r);
    kernels::addJacobi(r);
    kernels::addMaccormack(r);
    kernels::addMeshFractions(r);
    kernels::addMgCoarsenFaces(r);
    kernels::addMgCoarsenMask(r);
    kernels::addMgCoarsest(r);
    kernels::addMgProlong(r);
    kernels::addMgResidual(r);
    kernels::addMgResidualRestrict(r);
    kernels::addMgRestrict(r);
    kernels::addMgSmooth(r);
    kernels::addPcgApply(r);
    kernels::addPcgDirection(r);
    kernels::addPcgDot(r);
    kernels::addPcgInit(r);
    kernels::addPcgPredict(r);
    kernels::addPcgUpdate(r);
    kernels::addPressureShift(r);
    kernels::addPressureSum(r);
    kernels::addProject(r);
    kernels::addReduce(r);
    kernels::addResidual(r);
    kernels::addScalarCorrect(r);
    kernels::addScalarHeadroom(r);
    kernels::addScalarTotal(r);
    kernels::addSources(r);
    kernels::addSphereFractions(r);
    kernels::addVorticity(r);
    kernels::addVoxelizeMeshCrossings(r);
    kernels::addVoxelizeMeshFill(r);
    kernels::addVoxelizeMeshTransform(r);
    kernels::addVoxelizeMeshWinding(r);
    kernels::addVoxelizeSphere(r);
    return r;
  }();
  return registry;
}

}  // namespace hf::cpu
