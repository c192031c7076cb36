// core/input_policy.h — the one input policy of Unison (docs/input-policy.md): the ranges every number read from a
// file, a recording, the network or the C++ API must lie in, the largest counts, and the largest inputs.
//
// Owns: constants only, plus two tiny checks. Every reader (scene JSON 2D/3D, resolve JSON, LCP text, inputs JSON,
// recordings, snapshots, OBJ) and the worlds' createBody / setVelocity / applyImpulse / setGravity use these, so a
// limit is changed in one place and the document lists the same numbers.
// Why ranges and not only "finite": a velocity of 1e308 is finite but the first step turns it into infinity; every
// range below leaves many orders of magnitude before any product or square of two inputs can overflow a double.
#pragma once

#include <cmath>
#include <cstddef>

namespace unison::policy {

// ---- Simulation settings ----------------------------------------------------------------------------------------
constexpr double kMinHz = 1.0;                  ///< steps per second (dt <= 1 s)
constexpr double kMaxHz = 10000.0;              ///< steps per second (dt >= 0.1 ms)
constexpr double kMaxGravity = 1.0e4;           ///< |each gravity component| (m/s^2)
constexpr double kMaxRestitutionThreshold = 1.0e3;  ///< m/s
constexpr int kMinFrictionDirections = 4;       ///< 3D pyramid sides (even)
constexpr int kMaxFrictionDirections = 16;

// ---- Bodies and shapes -------------------------------------------------------------------------------------------
constexpr double kMaxCoordinate = 1.0e6;        ///< |each coordinate| of positions, points, vertices, offsets (m)
constexpr double kMaxAngle = 1.0e6;             ///< |angle| (rad), 2D
constexpr double kMaxSpeed = 1.0e4;             ///< |each linear velocity component| (m/s)
constexpr double kMaxAngularSpeed = 1.0e4;      ///< |each angular velocity component| (rad/s)
constexpr double kMinSize = 1.0e-4;             ///< smallest radius or half extent (m)
constexpr double kMaxSize = 1.0e6;              ///< largest radius or half extent (m)
constexpr double kMaxDensity = 1.0e6;           ///< kg/m^2 (2D) or kg/m^3 (3D); 0 is allowed (a massless shape)
constexpr double kMaxFriction = 10.0;           ///< Coulomb coefficient
constexpr double kMaxMeshScale = 1.0e6;         ///< a mesh's `scale`
constexpr std::size_t kMaxBodies = 100000;      ///< bodies of one scene
constexpr std::size_t kMaxShapesPerBody = 256;
constexpr std::size_t kMaxMeshVertices = std::size_t(1) << 20;
constexpr std::size_t kMaxMeshTriangles = std::size_t(1) << 21;

// ---- A world's state (snapshots, and the check after every step) -------------------------------------------------
// Wider than the creation ranges: bodies fall and speed up. A step that leaves these ranges stops the world with a
// clear error (World2/3::fault()), and restore() accepts exactly the states inside them, so a world's own snapshot
// always restores. At 1e9 m a double still resolves 0.1 micrometre.
constexpr double kMaxStateCoordinate = 1.0e9;   ///< |each coordinate| of a body's position and centre (m)
constexpr double kMaxStateSpeed = 1.0e9;        ///< |each component| of a linear (m/s) or angular (rad/s) velocity

// ---- Inputs (recordings, the network) ----------------------------------------------------------------------------
constexpr double kMaxImpulse = 1.0e9;           ///< |each impulse component| (N s)
constexpr double kMaxForce = 1.0e9;             ///< |each force component| (N)
constexpr int kMaxTick = 10000000;              ///< last tick of a recording or an input (46 h at 60 Hz)

// ---- The resolver on its own (`unison resolve`) ------------------------------------------------------------------
constexpr double kMinMass = 1.0e-6;             ///< kg
constexpr double kMaxMass = 1.0e12;             ///< kg
constexpr double kMinInertia = 1.0e-12;         ///< kg m^2 (2D scalar; 3D diagonal)
constexpr double kMaxInertia = 1.0e18;          ///< kg m^2 (|each entry|)
constexpr std::size_t kMaxResolveBodies = 10000;
constexpr std::size_t kMaxResolveContacts = 256;  ///< the friction LCP is dense: (k + 2) x 256 unknowns
/// Pivot cap of `unison resolve` per LCP unknown (plus 100): Lemke needs about one to two per unknown on real
/// contact sets; a crafted set that needs more is reported as pivot_limit in seconds, not minutes.
constexpr int kResolvePivotsPerUnknown = 4;

// ---- LCP text (`unison lcp`) -------------------------------------------------------------------------------------
constexpr std::size_t kMaxLcpSize = 1000;       ///< n
constexpr double kMaxLcpEntry = 1.0e30;         ///< |each entry of A and b|

// ---- Files and text ----------------------------------------------------------------------------------------------
constexpr std::size_t kMaxJsonBytes = std::size_t(8) << 20;     ///< scene, resolve and inputs JSON (8 MiB)
constexpr std::size_t kMaxJsonDepth = 64;                       ///< nesting of arrays and objects
constexpr std::size_t kMaxObjBytes = std::size_t(16) << 20;     ///< OBJ mesh files (16 MiB)
constexpr std::size_t kMaxLcpTextBytes = std::size_t(32) << 20; ///< LCP text files (32 MiB)
constexpr std::size_t kMaxBinaryBytes = std::size_t(128) << 20; ///< snapshots and recordings (128 MiB)

/// True when x is finite and |x| <= limit.
inline bool within(double x, double limit) { return std::isfinite(x) && std::fabs(x) <= limit; }
/// True when x is finite and lo <= x <= hi.
inline bool inRange(double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; }

}  // namespace unison::policy
