// unison/types.h — value types shared by the 2D and 3D worlds: body handles, body kinds, touch events, references
// to one shape of a body, step counts, and the exception the C++ API throws when a world cannot be created.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace unison {

/// Handle of a body: slot + 1 and the slot's generation when the body was created. A zero index1 is the null id;
/// a destroyed body's id stays invalid even after its slot is reused (the generation differs).
struct BodyId {
    std::uint32_t index1 = 0;      ///< slot index + 1; 0 for the null id
    std::uint32_t generation = 0;  ///< generation of the slot at creation; a stale id has an older one

    /// True for the null id (index1 == 0).
    bool isNull() const { return index1 == 0; }
    /// The null id, returned when no body could be created.
    static BodyId null() { return BodyId{}; }
};

/// Handles are equal when slot and generation both match.
inline bool operator==(BodyId a, BodyId b) { return a.index1 == b.index1 && a.generation == b.generation; }
/// Negation of operator==.
inline bool operator!=(BodyId a, BodyId b) { return !(a == b); }

/// Static bodies never move; kinematic bodies move with their velocity and have infinite mass; dynamic bodies
/// respond to gravity, contacts and impulses.
enum class BodyType : std::uint8_t { staticBody, kinematicBody, dynamicBody };

/// Two bodies started (begin) or stopped (end) touching with overlap during the last step.
struct TouchEvent {
    BodyId a, b;  ///< a before b by (generation, slot)
};

/// One shape of one body: the answer of an overlap query.
struct ShapeRef {
    BodyId body;    ///< the body
    int shape = 0;  ///< index into the body's shapes, in the order they were given at creation
};

/// Counts of the last step (contacts, islands, solver work); the same in 2D and 3D.
struct StepInfo {
    int islands = 0;                ///< islands of bodies joined by contacts
    int awakeIslands = 0;           ///< islands that were simulated (not asleep)
    int contacts = 0;               ///< contact points
    int pivots = 0;                 ///< Lemke pivots
    std::uint64_t work = 0;         ///< deterministic work units spent by the solver
    int failedIslands = 0;          ///< friction solves that fell back to the frictionless problem
    int unsolvedIslands = 0;        ///< islands that got no impulse at all
    double maxPenetration = 0.0;    ///< deepest overlap among touching contacts (m)
};

/// Thrown by the constructors of World2D and World3D: invalid settings, or a floating-point environment in which
/// results would not be bit-identical (flush-to-zero, another rounding mode, excess precision).
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace unison
