// core/single_contact_impl.h — the closed form of one 2D contact's friction LCP (detail::singleContactFriction),
// which resolveWithFriction tries before Lemke. Included by core/contact_resolver_impl.h where its helpers
// (makeRow, normalRhs, relativeVelocityAlong, applyImpulse) are defined; nothing else includes it.
#pragma once

namespace unison {
namespace detail {

// The friction LCP of one 2D contact (unknowns p_n, beta+, beta-, lambda) in closed form, the friction extension of the
// paper's single-point formula: with a = J M^-1 J^T of its normal and tangent rows and b their right-hand sides (as
// buildFrictionSystem), the contact separates (b_n >= 0: no impulse, lambda = |b_t|), sticks (a p = -b with p_n >= 0
// and |p_t| <= mu p_n) or slips with p_t = s mu p_n, s = +-1 (p_n = -b_n / (a_nn + s mu a_nt) > 0 and the sliding
// velocity u_t = b_t + a_tn p_n + s mu a_tt p_n opposes the impulse: s u_t <= 0), tried in that order. The answer is
// then checked on the whole 4 x 4 LCP with the rule of every Lemke answer (scaled residual <= tolerance). False, and
// the bodies untouched, when no case holds or the check fails (the caller goes on with Lemke).
template <class D>
bool singleContactFriction(std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c, const ResolverOptions& options,
                           Resolution& out) {
    const typename D::Vec t = D::tangentDirection(c.normal, 0, 2);
    const JacobianRow<D> rows[2] = {makeRow(bodies, c, c.normal), makeRow(bodies, c, t)};
    double a[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
    for (int s = 0; s < 2; ++s) {
        const ResolverBody<D>& B = bodies[std::size_t(rows[0].body[s])];
        if (isImmovable(B)) continue;
        for (int i = 0; i < 2; ++i) {
            for (int j = 0; j < 2; ++j) {
                a[i][j] += B.invMass * D::dot(rows[i].lin[s], rows[j].lin[s]) +
                           D::angDot(rows[i].ang[s], D::applyInvInertia(B.invInertia, rows[j].ang[s]));
            }
        }
    }
    const double bn = normalRhs(bodies, c, options.restitutionThreshold);
    const double vt = relativeVelocityAlong(bodies, c, t);
    const double deadZone = options.tangentDeadZone;
    const double bt = std::fabs(vt) <= deadZone ? 0.0 : vt;
    const double mu = c.friction;
    double pn = 0.0, pt = 0.0, lambda = 0.0;
    bool found = false;
    if (bn >= 0.0) {
        lambda = std::fabs(bt);
        found = true;
    }
    const double det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    if (!found && det > 0.0) {
        const double n = (a[0][1] * bt - a[1][1] * bn) / det;
        const double f = (a[1][0] * bn - a[0][0] * bt) / det;
        if (n >= 0.0 && std::fabs(f) <= mu * n) {
            pn = n;
            pt = f;
            found = true;
        }
    }
    for (int k = 0; k < 2 && !found; ++k) {
        const double s = k == 0 ? 1.0 : -1.0;
        const double den = a[0][0] + s * mu * a[0][1];
        if (!(den > 0.0)) continue;
        const double n = -bn / den;
        const double ut = bt + a[1][0] * n + s * mu * a[1][1] * n;
        if (n >= 0.0 && s * ut <= 0.0) {
            pn = n;
            pt = s * mu * n;
            lambda = -s * ut;
            found = true;
        }
    }
    if (!found) return false;
    // The whole LCP: z = (p_n, beta+, beta-, lambda), w = A z + b, rows n, +t, -t, slack.
    const double z[4] = {pn, std::max(pt, 0.0), std::max(-pt, 0.0), lambda};
    const double un = bn + a[0][0] * z[0] + a[0][1] * (z[1] - z[2]);
    const double ut = bt + a[1][0] * z[0] + a[1][1] * (z[1] - z[2]);
    const double w[4] = {un, ut + lambda, -ut + lambda, mu * z[0] - z[1] - z[2]};
    double residual = 0.0;
    for (int i = 0; i < 4; ++i) residual = std::max(residual, std::fabs(std::min(z[i], w[i])));
    const double scale = std::max({1.0, mu, std::fabs(a[0][0]), std::fabs(a[0][1]), std::fabs(a[1][0]),
                                   std::fabs(a[1][1]), std::fabs(bn), std::fabs(bt)});
    const double scaled = residual / scale;
    if (!(scaled <= options.lcp.residualTolerance)) return false;
    out.status = LcpStatus::solved;
    out.fastPath = true;
    out.residual = residual;
    out.scaledResidual = scaled;
    out.work = 0;  // the world charges the whole closed form as one (work::kClosedFormIsland)
    out.basis.clear();
    out.basis.reserve(4);
    for (int i = 0; i < 4; ++i) {
        if (z[i] > 0.0) out.basis.push_back(i);
    }
    const std::vector<int>* guess = options.lcp.warmBasis;
    out.warmStarted = guess && !guess->empty();  // a guess is never wrong here: no solve needed one
    out.impulses.assign(1, pn);
    const typename D::Vec ft = D::scale(pt, t);
    out.tangentImpulses.assign(D::kDim, 0.0);
    for (int d = 0; d < D::kDim; ++d) out.tangentImpulses[std::size_t(d)] = ft[d];
    applyImpulse(bodies, c, D::add(D::scale(pn, c.normal), ft));  // as applyImpulses, without a vector of one
    return true;
}

}  // namespace detail

}  // namespace unison
