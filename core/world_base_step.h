// core/world_base_step.h — WorldBase's step and body operations (core/world_base.h). Included by a world's own .cpp
// after its Hooks, where they are explicitly instantiated; every other file sees only the declarations.
#pragma once

#include "world_base.h"

namespace unison {

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
bool WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::destroyBody(BodyId id) {
    if (!mBodies.destroy(id)) return false;
    mStep.cache.forgetSlot(id.index1);
    mIndex->invalidate();
    return true;
}

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
BodyId WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::addBody(const Hot& hot, const Cold& cold,
                                                                   std::string* error) {
    const BodyId id = mBodies.create(hot, cold);
    if (id.isNull()) {
        if (error) *error = "world: body capacity reached";
        return id;
    }
    mIndex->invalidate();
    return id;
}

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
void WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::step(std::uint64_t budget) {
    if (!mFault.empty()) return;  // never step a state that holds NaN or infinity
    mIndex->invalidate();
    self().beforeStep();
    typename Derived::Hooks hooks{self()};
    mStep.run(hooks, StepControl{budget, taskFieldsOf(mDef)});
    ++mStepCount;
    // The scan over every body (and the message) only when a body the step moved left the supported ranges.
    mFault = mStep.motionFault() ? self().findFault() : std::string();
}

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
bool WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::setVelocity(BodyId id, const Vec& linear, const Ang& angular) {
    const int d = mBodies.denseIndex(id);
    if (d < 0 || !D::componentsWithin(linear, policy::kMaxSpeed) ||
        !D::angComponentsWithin(angular, policy::kMaxAngularSpeed))
        return false;
    Cold& info = mBodies.cold(d);
    if (info.type == BodyType::staticBody) return false;
    mBodies.hot(d).velocity = linear;
    mBodies.hot(d).angularVelocity = angular;
    info.awake = true;
    info.sleepTime = 0.0;
    return true;
}

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
bool WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::applyImpulse(BodyId id, const Vec& impulse,
                                                                      const Vec& worldPoint) {
    const int d = mBodies.denseIndex(id);
    if (d < 0 || !D::componentsWithin(impulse, policy::kMaxImpulse) || !D::finite(worldPoint)) return false;
    Cold& info = mBodies.cold(d);
    if (info.type != BodyType::dynamicBody) return false;
    Hot& s = mBodies.hot(d);
    const auto invI = Derived::worldInvInertia(s, info);
    s.velocity = D::add(s.velocity, D::scale(info.invMass, impulse));
    s.angularVelocity = D::angAdd(s.angularVelocity, D::applyInvInertia(invI, D::cross(D::sub(worldPoint, s.center), impulse)));
    info.awake = true;
    info.sleepTime = 0.0;
    return true;
}

}  // namespace unison
