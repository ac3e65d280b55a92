// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The kernel files of cpu/kernels/: each adds its shader's variants to the registry.
#include "cpu/kernel.h"

namespace hf::cpu::kernels {

void addAdvect(KernelRegistry& r);
void addApplyForces(KernelRegistry& r);
void addBinaryFractions(KernelRegistry& r);
void addCellForces(KernelRegistry& r);
void addClassify(KernelRegistry& r);
void addDivergence(KernelRegistry& r);
void addEmitCoverage(KernelRegistry& r);
void addEmitMeshCoverage(KernelRegistry& r);
void addEmitMeshCrossings(KernelRegistry& r);
void addEnforceBoundaries(KernelRegistry& r);
void addForceFaces(KernelRegistry& r);
void addJacobi(KernelRegistry& r);
void addMaccormack(KernelRegistry& r);
void addMeshFractions(KernelRegistry& r);
void addMgCoarsenFaces(KernelRegistry& r);
void addMgCoarsenMask(KernelRegistry& r);
void addMgCoarsest(KernelRegistry& r);
void addMgProlong(KernelRegistry& r);
void addMgResidual(KernelRegistry& r);
void addMgResidualRestrict(KernelRegistry& r);
void addMgRestrict(KernelRegistry& r);
void addMgSmooth(KernelRegistry& r);
void addPcgApply(KernelRegistry& r);
void addPcgDirection(KernelRegistry& r);
void addPcgDot(KernelRegistry& r);
void addPcgInit(KernelRegistry& r);
void addPcgPredict(KernelRegistry& r);
void addPcgUpdate(KernelRegistry& r);
void addPressureShift(KernelRegistry& r);
void addPressureSum(KernelRegistry& r);
void addProject(KernelRegistry& r);
void addReduce(KernelRegistry& r);
void addResidual(KernelRegistry& r);
void addScalarCorrect(KernelRegistry& r);
void addScalarHeadroom(KernelRegistry& r);
void addScalarTotal(KernelRegistry& r);
void addSources(KernelRegistry& r);
void addSphereFractions(KernelRegistry& r);
void addVorticity(KernelRegistry& r);
void addVoxelizeMeshCrossings(KernelRegistry& r);
void addVoxelizeMeshFill(KernelRegistry& r);
void addVoxelizeMeshTransform(KernelRegistry& r);
void addVoxelizeMeshWinding(KernelRegistry& r);
void addVoxelizeSphere(KernelRegistry& r);

}  // namespace hf::cpu::kernels
