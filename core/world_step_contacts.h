// core/world_step_contacts.h — the contact finding of core/world_step.h (included at its end): one parallel pass
// over bodies (gravity, then each shape's box grown by its speculative reach), the broadphase, the narrowphase over
// its pairs, and the gathering of the points in pair order with each contact's island edge, warm-start cache entry
// and touch pair.
//
// Owns no state. Each parallel pass writes only its item's outputs (a body's boxes, a pair's slots, a contact's
// entries) and per-worker sums, so the contacts come out the same for any thread count.
#pragma once

#include "world_step.h"

namespace unison {

template <class D>
template <class H>
void WorldStep<D>::findContacts(H& hooks) {
    const auto& def = hooks.def();
    auto& hot = hooks.bodies().hotArray();
    const auto& cold = hooks.bodies().coldArray();
    struct Proxy {
        int body, shape;
        double far;  // how far the shape can move this step (m): dt (|v| + |w| extent), or more (below)
    };
    // Proxies, boxes and flags in (body, shape) order, each body's at its own offset (mFirst), so bodies fill them
    // in parallel. A body's shapes are fixed when it is created, so the offsets change only when bodies come and go:
    // they are kept with the shape counts they were made from, and the body pass checks each body's count against
    // its kept one (reading cold records here, on one thread, would pull every body's record away from the thread
    // that integrates it). A count that differs, or another number of bodies, makes new offsets.
    const int nb = int(hot.size());
    auto layOut = [&] {
        mShapeCount.resize(std::size_t(nb));
        mFirst.assign(std::size_t(nb) + 1, 0);
        for (int d = 0; d < nb; ++d) {
            mShapeCount[std::size_t(d)] = int(cold[std::size_t(d)].shapes.size());
            mFirst[std::size_t(d) + 1] = mFirst[std::size_t(d)] + mShapeCount[std::size_t(d)];
        }
    };
    if (mFirst.size() != std::size_t(nb) + 1) layOut();
    std::size_t nproxies = std::size_t(mFirst[std::size_t(nb)]);
    std::vector<Proxy> proxies(nproxies);
    std::vector<decltype(computeAabb(cold[0].shapes[0], hooks.transform(hot[0])))> boxes(nproxies);
    std::vector<std::uint8_t> inactive(nproxies);
    std::vector<decltype(hooks.transform(hot[0]))> xfs(hot.size());
    const double margin = def.speculativeDistance;
    const double band = hooks.speculativeBand();
    const bool finiteBand = band < std::numeric_limits<double>::infinity();
    const double dt = 1.0 / def.hz;
    // Relative normal speed of two bodies at a point (A minus B along n; < 0 when closing), before the solve.
    auto closingSpeed = [](const auto& sa, const auto& sb, const Vec& p, const Vec& n) {
        const Vec va = D::add(sa.velocity, D::angularVelocityAt(sa.angularVelocity, D::sub(p, sa.center)));
        const Vec vb = D::add(sb.velocity, D::angularVelocityAt(sb.angularVelocity, D::sub(p, sb.center)));
        return D::dot(n, D::sub(va, vb));
    };
    auto length = [](const Vec& v) { return std::sqrt(D::dot(v, v)); };
    mGraphChanged = int(mJoins.size()) != nb;
    mJoins.resize(std::size_t(nb));
    if (mWorkers.empty()) mWorkers.resize(1);
    for (Worker& w : mWorkers) {
        w.kinematicBodies = 0;
        w.graphChanged = false;
        w.sleepers = false;
        w.shapesChanged = false;
    }
    // A body's shapes' boxes (after its velocity and transform are this step's) at its offset in mFirst.
    auto placeShapes = [&](int d) {
        const auto& st = hot[std::size_t(d)];
        const auto& info = cold[std::size_t(d)];
        for (int s = 0; s < int(info.shapes.size()); ++s) {
            auto box = computeAabb(info.shapes[std::size_t(s)], xfs[std::size_t(d)]);
            // Speculative reach: a contact that can close within this step must already be in this step's LCP, or
            // fast bodies sink deep before they are seen (and position correction then adds energy). Static bodies
            // do not move (and a 3D plane's box is unbounded).
            // With a finite band (3D), the reach also covers what the solve can do to the shape's motion: a cube
            // that lands on one corner turns about it, and its next corners then close faster than any point moved
            // before the solve. hooks.speedBound is the fastest any point within `extent` of the centre can move
            // with the body's present kinetic energy, which contacts do not add to. (The 2D world keeps every
            // point within the reach in the LCP, so there a larger reach would only grow islands.)
            double reach = 0.0, far = 0.0;
            if (!world_step_detail::isStatic(info)) {
                const Vec half = D::scale(0.5, D::sub(box.upper, box.lower));
                const Vec mid = D::scale(0.5, D::add(box.upper, box.lower));
                const double extent = length(half) + length(D::sub(mid, st.center));
                reach = dt * (length(st.velocity) + D::angNorm(st.angularVelocity) * extent);
                far = finiteBand ? std::max(reach, dt * hooks.speedBound(st, info, extent)) : reach;
            }
            const double grow = margin + far;
            box.lower = D::sub(box.lower, D::uniform(grow));
            box.upper = D::add(box.upper, D::uniform(grow));
            const std::size_t k = std::size_t(mFirst[std::size_t(d)] + s);
            proxies[k] = {d, s, far};
            boxes[k] = box;
            inactive[k] = world_step_detail::isDynamic(info) ? 0 : 1;
        }
    };
    forEach(nb, 64, [&](int d, Worker& worker) {
        auto& st = hot[std::size_t(d)];
        const auto& info = cold[std::size_t(d)];
        const bool dynamic = world_step_detail::isDynamic(info);
        if (world_step_detail::isKinematic(info)) ++worker.kinematicBodies;
        if (dynamic && info.awake) st.velocity = D::add(st.velocity, D::scale(dt, def.gravity));  // external forces
        worker.sleepers = worker.sleepers || (dynamic && !info.awake);
        xfs[std::size_t(d)] = hooks.transform(st);
        const std::uint8_t joins = dynamic ? 1 : 0;
        worker.graphChanged = worker.graphChanged || mJoins[std::size_t(d)] != joins;
        mJoins[std::size_t(d)] = joins;
        if (int(info.shapes.size()) != mShapeCount[std::size_t(d)]) worker.shapesChanged = true;  // (placed below)
        else placeShapes(d);
    });
    bool shapesChanged = false;
    for (const Worker& w : mWorkers) shapesChanged = shapesChanged || w.shapesChanged;
    if (shapesChanged) {  // bodies came and went since the offsets were made: new offsets, and every box again
        layOut();
        nproxies = std::size_t(mFirst[std::size_t(nb)]);
        proxies.resize(nproxies);
        boxes.resize(nproxies);
        inactive.resize(nproxies);
        forEach(nb, 64, [&](int d, Worker&) { placeShapes(d); });
    }
    mAllAwake = true;
    for (const Worker& w : mWorkers) mAllAwake = mAllAwake && !w.sleepers;
    // The sweep over the sorted boxes in parallel chunks (the sorted pairs do not depend on them).
    const ChunkRunner sweepRunner = [this](int chunks, const std::function<void(int)>& fn) {
        forEach(chunks, 1, [&](int c, Worker&) { fn(c); });
    };
    const auto pairs = findPairs(boxes, inactive, &mSweep, &sweepRunner);
    // The narrowphase in parallel: each pair writes its points into its own slots; they are gathered in pair order.
    using Manifold = decltype(hooks.narrowphase(cold[0].shapes[0], xfs[0], cold[0].shapes[0], xfs[0], 0.0, mStats));
    constexpr int kSlots = int(std::tuple_size<std::decay_t<decltype(std::declval<Manifold>().points)>>::value);
    const int np = int(pairs.size());
    if (mSlots.size() < std::size_t(np) * kSlots) mSlots.resize(std::size_t(np) * kSlots);  // kept between steps
    StepContact<D>* slots = mSlots.data();
    std::vector<int> counts(std::size_t(np), 0);
    std::vector<std::uint64_t> pairWork(std::size_t(np), 0);
    for (Worker& w : mWorkers) w.collide = StepStats{};  // (workers created later start empty too)
    auto collidePair = [&](int i, Worker& worker) {
        const Proxy& pa = proxies[std::size_t(pairs[std::size_t(i)].first)];
        const Proxy& pb = proxies[std::size_t(pairs[std::size_t(i)].second)];
        if (pa.body == pb.body) return;
        const auto& shA = cold[std::size_t(pa.body)].shapes[std::size_t(pa.shape)];
        const auto& shB = cold[std::size_t(pb.body)].shapes[std::size_t(pb.shape)];
        const Manifold m = hooks.narrowphase(shA, xfs[std::size_t(pa.body)], shB, xfs[std::size_t(pb.body)],
                                             margin + pa.far + pb.far, worker.collide);
        pairWork[std::size_t(i)] = hooks.pairWork(shA, shB, m);
        // A gap that the bodies' present motion cannot bring within `band` this step stays out of the LCP: it adds
        // no rows and joins no islands (the isotropic reach above finds such points for fast bodies, and resting
        // neighbours 1-2 cm apart would otherwise fuse separate stacks into one big island). But once one point of
        // the pair is in, the pair's island is joined anyway, and every point of its manifold (all within the
        // bodies' `far`) enters with it: the solve that stops that point turns the bodies about it.
        bool pairIn = false;
        for (int k = 0; k < m.count && !pairIn; ++k) {
            const auto& mp = m.points[std::size_t(k)];
            pairIn = mp.separation <= 0.0 ||
                     mp.separation + dt * std::min(0.0, closingSpeed(hot[std::size_t(pa.body)], hot[std::size_t(pb.body)],
                                                                      mp.point, hooks.normalOf(m, k))) < band;
        }
        int kept = 0;
        for (int k = 0; pairIn && k < m.count; ++k) {
            const auto& mp = m.points[std::size_t(k)];
            StepContact<D>& c = slots[std::size_t(i) * kSlots + std::size_t(kept++)];
            c = StepContact<D>{};
            c.point = mp.point;
            c.normal = hooks.normalOf(m, k);
            c.separation = mp.separation;
            c.feature = mp.id;
            c.bodyA = pa.body;
            c.bodyB = pb.body;
            c.shapeA = pa.shape;
            c.shapeB = pb.shape;
            c.friction = std::sqrt(shA.friction * shB.friction);  // mixing as in Box2D
            c.restitution = std::max(shA.restitution, shB.restitution);
        }
        counts[std::size_t(i)] = kept;
    };
    if (mWorkers.empty()) mWorkers.resize(1);
    if (hooks.parallelNarrowphase()) {
        forRanges(np, 16, [&](int begin, int end, Worker& worker) {
            [[maybe_unused]] const auto scope = hooks.narrowphaseScope();  // what one thread may keep across pairs
            for (int i = begin; i < end; ++i) collidePair(i, worker);
        });
    } else {
        [[maybe_unused]] const auto scope = hooks.narrowphaseScope();
        for (int i = 0; i < np; ++i) collidePair(i, mWorkers[0]);
    }
    // The points gathered in pair order, in parallel from each pair's offset, and with each its island edge, its
    // warm-start cache entry and its touch pair. Contacts come in nearly ascending key order, so each range starts
    // with a search and then tries the entry after the last hit first. The per-contact arrays keep their size from
    // the last step, so only growth is initialised here.
    std::vector<int> offset(std::size_t(np) + 1, 0);
    for (int i = 0; i < np; ++i) offset[std::size_t(i) + 1] = offset[std::size_t(i)] + counts[std::size_t(i)];
    const std::size_t nc = std::size_t(offset[std::size_t(np)]);
    mContacts.resize(nc);
    mGraphChanged = mGraphChanged || mEdges.size() != nc;
    mEdges.resize(nc);
    mHit.resize(nc);
    mNewEntry.resize(nc);
    mHasEntry.assign(nc, 0);
    mTouch.resize(nc);
    const auto& store = hooks.bodies();
    for (Worker& w : mWorkers) w.narrowWork = 0;
    forRanges(np, 256, [&](int begin, int end, Worker& worker) {
        int hint = -1;
        for (int i = begin; i < end; ++i) {
            worker.narrowWork += pairWork[std::size_t(i)];
            for (int k = 0; k < counts[std::size_t(i)]; ++k) {
                const std::size_t ci = std::size_t(offset[std::size_t(i)] + k);
                const StepContact<D>& c = mContacts[ci] = slots[std::size_t(i) * kSlots + std::size_t(k)];
                worker.graphChanged = worker.graphChanged || mEdges[ci].a != c.bodyA || mEdges[ci].b != c.bodyB;
                mEdges[ci] = {c.bodyA, c.bodyB};
                const int hit = cache.findFrom(keyOf(hooks, c), hint);
                mHit[ci] = hit;
                hint = hit >= 0 ? hit + 1 : hint;
                // Touching with overlap: the pair's keys (a < b), else {0, 0} (no key is 0).
                std::uint64_t ka = 0, kb = 0;
                if (c.separation < 0.0) {
                    ka = touchKey(store.idAt(c.bodyA));
                    kb = touchKey(store.idAt(c.bodyB));
                    if (kb < ka) std::swap(ka, kb);
                }
                mTouch[ci] = {ka, kb};
            }
        }
    });
    std::uint64_t narrow = 0;  // a sum of integers: the same in any order
    for (const Worker& w : mWorkers) {
        narrow += w.narrowWork;
        mStats.candidates += w.collide.candidates;
        mGraphChanged = mGraphChanged || w.graphChanged;
    }
    mFixedWork += work::kPerBody * hot.size() + work::kPerShape * proxies.size() + work::kPerPair * pairs.size() + narrow;
}

}  // namespace unison
