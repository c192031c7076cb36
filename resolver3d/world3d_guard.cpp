// resolver3d/world3d_guard.cpp — the check after every 3D step that its numbers are still finite (World3::fault();
// the reasons are those of resolver2d/world2d_guard.cpp).
#include "world3d.h"

#include <cmath>

namespace unison {

std::string World3::findNonFinite() const {
    for (const BodyState3& s : mBodies.hotArray()) {
        const Quat& q = s.rotation;
        const bool finite = Dim3::finite(s.position) && Dim3::finite(s.center) && Dim3::finite(s.velocity) &&
                            Dim3::finite(s.angularVelocity) && std::isfinite(q.w) && std::isfinite(q.x) &&
                            std::isfinite(q.y) && std::isfinite(q.z);
        if (!finite) return "step " + std::to_string(mStepCount) + " overflowed: " + firstNonFinite(stateFields());
    }
    return {};
}

}  // namespace unison
