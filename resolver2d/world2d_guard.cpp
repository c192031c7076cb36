// resolver2d/world2d_guard.cpp — the check after every 2D step that its numbers are still finite (World2::fault()).
//
// Why: inputs within core/input_policy.h keep every number many orders of magnitude below overflow, but a world
// built through the C++ API with settings outside it (dt = 1e300, say) could be flung to infinity. A NaN must not
// then travel on silently: the next step would sort bounding boxes of NaN (undefined behaviour in std::sort) and
// print `null` for positions. The check reads the hot records only (10 doubles per body), so it costs nothing next
// to the step; the slow named-field walk runs only once something is wrong, to say which body and field.
#include "world2d.h"

#include <cmath>

namespace unison {

std::string World2::findNonFinite() const {
    for (const BodyState2& s : mBodies.hotArray()) {
        const double v[] = {s.position.x, s.position.y, s.rotation.c, s.rotation.s, s.center.x,
                            s.center.y,   s.velocity.x, s.velocity.y, s.angularVelocity};
        for (double x : v) {
            if (!std::isfinite(x))
                return "step " + std::to_string(mStepCount) + " overflowed: " + firstNonFinite(stateFields());
        }
    }
    return {};
}

}  // namespace unison
