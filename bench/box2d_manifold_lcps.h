// bench/box2d_manifold_lcps.h — contact LCPs assembled from Box2D 2.4.1's own contact manifolds.
//
// Owns: a snapshot of what Box2D's collision pipeline hands its solver after a testbed pyramid has settled (contact
// points, normals, friction; body centres, inverse masses and inertias, velocities, all in Box2D's single
// precision), and the contact LCPs assembled from it in Unison's layout:
//   frictionless  A = N M^-1 N^T, b = N v                                  (n = contacts)
//   friction      Stewart-Trinkle pyramid as core/contact_resolver.h's assembleFrictionLcp builds it: unknowns
//                 [normals (nc) | tangents (2 nc, +t then -t per contact) | slacks (nc)], A's coupling block
//                 J M^-1 J^T with J = [N ; D], E and mu blocks, b = [N v ; D v ; 0]  (n = 4 nc)
// v is the velocity the next step's solver sees: Box2D's velocity after the step plus one step of gravity.
// A settled pyramid has more contact rows than body degrees of freedom (2 rows^2 points on 1.5 rows (rows + 1)
// velocity components), so the rows are redundant and A is singular.
//
// Every LCP comes twice:
//   double data  Box2D's float values read exactly into doubles and assembled by Unison's own assembler in double:
//                A is positive semi-definite to double rounding and b lies in A's range to rounding, so the LCP is
//                solvable and a correct solver must end `solved` (scaled residual <= 1e-9);
//   float data   the Jacobian rows (r = p - c, r x n), the masses and every product and sum of A and b computed in
//                float as Box2D computes them: A is indefinite at ~1e-8 of its scale and b lies off its range at
//                ~1e-6, so an exact solution may not exist and the best answer is at the data's noise level.
//
// Invariants: contacts are ordered by (scene index of Box2D's body A, of body B, point index), never by pointer;
// bodies are indexed as in the scene. Box2D's run is deterministic, so the LCPs are the same on every run.
#pragma once

#include "contact_resolver.h"
#include "dim2.h"
#include <unison/lcp.h>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace unison::bench {

class Box2dPeer;

/// One body as Box2D's solver sees it (single precision, as stored by Box2D).
struct ManifoldBody {
    float cx = 0.0f, cy = 0.0f;  ///< centre of mass (m)
    float vx = 0.0f, vy = 0.0f;  ///< centre-of-mass velocity including one step of gravity (m/s)
    float w = 0.0f;              ///< angular velocity (rad/s)
    float invMass = 0.0f;        ///< 1 / kg (0: static)
    float invI = 0.0f;           ///< 1 / (kg m^2) about the centre of mass (0: static)
};

/// One manifold point in Unison's convention: normal away from body b towards body a.
struct ManifoldPoint {
    int a = -1, b = -1;          ///< scene body indices (a = Box2D's body B, b = Box2D's body A)
    float px = 0.0f, py = 0.0f;  ///< world point, midway between the surfaces (b2WorldManifold)
    float nx = 0.0f, ny = 0.0f;  ///< unit normal (b2WorldManifold::normal, from Box2D's A to B)
    float friction = 0.0f;       ///< mixed friction of the contact
};

/// What Box2D's pipeline produced at one step: every scene body and every touching manifold point.
struct ManifoldSnapshot {
    std::vector<ManifoldBody> bodies;    ///< (scene bodies)
    std::vector<ManifoldPoint> points;   ///< (contacts), ordered as the header says
    int dynamicBodies = 0;               ///< bodies with invMass > 0
};

/// Reads the touching contacts of `peer`'s world after its last step; the dynamic bodies' velocities get one step
/// (1 / peer.hz() s) of the vertical gravity `gravityY` (m/s^2), in float as Box2D integrates it.
ManifoldSnapshot captureManifolds(const Box2dPeer& peer, double gravityY);

/// Precision of an assembly.
enum class ManifoldData { doubleData, floatData };

/// The LCP of `snap` (friction: the Stewart-Trinkle layout above; else frictionless). doubleData uses Unison's
/// assembleCollisionLcpSparse / assembleFrictionLcpSparse on the exact double values of the snapshot; floatData
/// assembles in float arithmetic.
SparseLcp assembleManifoldLcp(const ManifoldSnapshot& snap, bool friction, ManifoldData data);

/// The same rows as floatData but with double arithmetic: differs from the doubleData assembly only by the order
/// of roundings (a check of the float assembler's layout).
SparseLcp assembleManifoldLcpRowsInDouble(const ManifoldSnapshot& snap, bool friction);

/// Bodies and contact nodes of `snap` as core/contact_resolver takes them (double values of the floats; e = 0).
void toResolverInput(const ManifoldSnapshot& snap, std::vector<ResolverBody<Dim2>>* outBodies,
                     std::vector<ContactNode<Dim2>>* outContacts);

/// A named member of the family.
struct ManifoldLcp {
    std::string name;         ///< e.g. "b2m_pyramid20_friction_float"
    int rows = 0;             ///< pyramid rows
    bool friction = false;    ///< Stewart-Trinkle (else frictionless)
    ManifoldData data = ManifoldData::doubleData;
    int contacts = 0;         ///< manifold points
    int dynamicBodies = 0;
    SparseLcp lcp;
};

/// Steps of settling by default: 4 s, well after a 30-row pyramid's top box has landed (1.2 s).
constexpr int kDefaultSettleSteps = 240;
/// Settles scenes::pyramidScene(rows, 0.5, false) in Box2D 2.4.1 for `settleSteps` steps (8 velocity, 3 position
/// iterations, 60 Hz) and returns its snapshot.
ManifoldSnapshot settledPyramidSnapshot(int rows, int settleSteps = kDefaultSettleSteps);

/// The family for each pyramid size in `rows`: per size, frictionless double, frictionless float, friction double,
/// friction float (in that order).
std::vector<ManifoldLcp> box2dManifoldLcps(const std::vector<int>& rows = {12, 20, 30},
                                           int settleSteps = kDefaultSettleSteps);

/// The four members of one snapshot (the order of box2dManifoldLcps).
std::vector<ManifoldLcp> manifoldLcpsOf(const ManifoldSnapshot& snap, int rows);

/// Stable lower-case name of a data kind: "double" or "float".
const char* dataName(ManifoldData data);

/// max_i |min(z_i, w_i)| with w = A z + b recomputed here, divided by max(max|A_ij|, max|b_i|) (1 if both are 0):
/// the rule of scenes::scaledResidual on a sparse matrix. +infinity when z has the wrong size or a non-finite entry.
double scaledResidual(const SparseLcp& lcp, const std::vector<double>& z);

/// The dense form of a sparse LCP (n x n; mind n^2 memory).
Lcp toDense(const SparseLcp& lcp);

}  // namespace unison::bench
