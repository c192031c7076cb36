// samples/view_capture.cpp — re-simulates a recording and captures every tick for the viewer (see view_capture.h).
//
// Shape JSON, body frame: 2D {"t": "circle", "c": [x, y], "r"}, {"t": "poly", "v": [[x, y], ...]},
// {"t": "seg", "p": [[x, y], [x, y]]}; 3D {"t": "sphere", "c", "r"}, {"t": "poly", "g": index of a geometry entry
// {"v": vertices, "e": [[i, j], ...]}} (boxes and hulls), {"t": "plane", "n", "d"}, {"t": "mesh", "g": index of
// {"v", "f": triangles}}.
#include "view_capture.h"

#include "island.h"

#include <cmath>
#include <limits>
#include <map>

namespace unison::view {
namespace {

using nlohmann::json;

json vec(double x, double y) { return json::array({float(x), float(y)}); }
json vec(const Vec3& v) { return json::array({float(v.x()), float(v.y()), float(v.z())}); }

const char* typeName(bool isStatic, bool isKinematic) { return isStatic ? "static" : isKinematic ? "kinematic" : "dynamic"; }

/// The 2D world's part of the capture.
struct Dim2View {
    using World = World2;
    static constexpr int kDim = 2, kPose = 3, kContact = 6;
    json bodyJson(const World2& w, BodyId id, json&) {
        const BodyInfo2& info = *w.info(id);
        json shapes = json::array();
        for (const Shape2& s : info.shapes) {
            if (s.type == ShapeType::circle) {
                shapes.push_back({{"t", "circle"}, {"c", vec(s.circle.center.x, s.circle.center.y)}, {"r", float(s.circle.radius)}});
            } else if (s.type == ShapeType::polygon) {
                json v = json::array();
                for (int i = 0; i < s.polygon.count; ++i)
                    v.push_back(vec(s.polygon.vertices[std::size_t(i)].x, s.polygon.vertices[std::size_t(i)].y));
                shapes.push_back({{"t", "poly"}, {"v", v}});
            } else {
                shapes.push_back({{"t", "seg"}, {"p", {vec(s.segment.p1.x, s.segment.p1.y), vec(s.segment.p2.x, s.segment.p2.y)}}});
            }
        }
        return {{"type", typeName(info.type == BodyType::staticBody, info.type == BodyType::kinematicBody)}, {"shapes", shapes}};
    }
    static bool isDynamic(const World2& w, BodyId id) { return w.info(id)->type == BodyType::dynamicBody; }
    static bool isStatic(const World2& w, BodyId id) { return w.info(id)->type == BodyType::staticBody; }
    static bool awake(const World2& w, BodyId id) { return w.info(id)->awake; }
    static void pose(const World2& w, BodyId id, float* out) {
        const BodyState2& s = *w.state(id);
        out[0] = float(s.position.x);
        out[1] = float(s.position.y);
        out[2] = float(w.angle(id));
    }
    static void contact(const ContactPoint2& c, float* out) {
        const float v[kContact] = {float(c.point.x), float(c.point.y), float(c.normal.x), float(c.normal.y),
                                   float(c.normalImpulse), float(c.tangentImpulse)};
        std::copy(v, v + kContact, out);
    }
};

/// The 3D world's part of the capture: boxes, hulls and meshes refer to shared geometry entries.
struct Dim3View {
    using World = World3;
    static constexpr int kDim = 3, kPose = 7, kContact = 10;
    std::map<const void*, int> known;  // geometry already in the table
    int geometryIndex(const void* key, json& geometry, json entry) {
        const auto it = known.find(key);
        if (it != known.end()) return it->second;
        geometry.push_back(std::move(entry));
        return known[key] = int(geometry.size()) - 1;
    }
    json bodyJson(const World3& w, BodyId id, json& geometry) {
        const BodyInfo3& info = *w.info(id);
        json shapes = json::array();
        for (const Shape3& s : info.shapes) {
            switch (s.type) {
                case ShapeType3::sphere: shapes.push_back({{"t", "sphere"}, {"c", vec(s.center)}, {"r", float(s.radius)}}); break;
                case ShapeType3::plane: shapes.push_back({{"t", "plane"}, {"n", vec(s.normal)}, {"d", float(s.offset)}}); break;
                case ShapeType3::box:
                case ShapeType3::hull: {
                    json v = json::array(), e = json::array();
                    for (const Vec3& p : s.poly->vertices) v.push_back(vec(p));
                    for (const auto& edge : s.poly->edges) e.push_back({edge.v0, edge.v1});
                    shapes.push_back({{"t", "poly"}, {"g", geometryIndex(s.poly.get(), geometry, {{"v", v}, {"e", e}})}});
                    break;
                }
                case ShapeType3::mesh: {
                    json v = json::array(), f = json::array();
                    for (const Vec3& p : s.mesh->vertices) v.push_back(vec(p));
                    for (const auto& t : s.mesh->triangles) f.push_back({t[0], t[1], t[2]});
                    shapes.push_back({{"t", "mesh"}, {"g", geometryIndex(s.mesh.get(), geometry, {{"v", v}, {"f", f}})}});
                    break;
                }
            }
        }
        return {{"type", typeName(info.type == BodyType::staticBody, info.type == BodyType::kinematicBody)}, {"shapes", shapes}};
    }
    static bool isDynamic(const World3& w, BodyId id) { return w.info(id)->type == BodyType::dynamicBody; }
    static bool isStatic(const World3& w, BodyId id) { return w.info(id)->type == BodyType::staticBody; }
    static bool awake(const World3& w, BodyId id) { return w.info(id)->awake; }
    static void pose(const World3& w, BodyId id, float* out) {
        const BodyState3& s = *w.state(id);
        const float v[kPose] = {float(s.position.x()), float(s.position.y()), float(s.position.z()), float(s.rotation.w),
                                float(s.rotation.x), float(s.rotation.y), float(s.rotation.z)};
        std::copy(v, v + kPose, out);
    }
    static void contact(const ContactPoint3& c, float* out) {
        const float v[kContact] = {float(c.point.x()), float(c.point.y()), float(c.point.z()), float(c.normal.x()),
                                   float(c.normal.y()), float(c.normal.z()), float(c.normalImpulse),
                                   float(c.tangentImpulse.x()), float(c.tangentImpulse.y()), float(c.tangentImpulse.z())};
        std::copy(v, v + kContact, out);
    }
};

/// One frame before the body count is known.
struct Frame {
    std::vector<float> poses;             // (numbers seen so far x stride)
    std::vector<std::uint16_t> islands;   // (numbers seen so far)
};

template <class V>
Capture captureWith(const replay::Recording& rec) {
    using World = typename V::World;
    V dim;
    Capture cap;
    cap.dimension = V::kDim;
    cap.ticks = rec.steps;
    cap.poseStride = V::kPose;
    cap.contactStride = V::kContact;
    cap.bodies = json::array();
    cap.geometry = json::array();
    replay::Session<World> session(rec.scene, "recording scene");
    cap.hz = session.world().def().hz;
    std::vector<Frame> frames;
    json pivots = json::array(), work = json::array(), contacts = json::array(), islandCount = json::array(),
         awakeIslands = json::array(), penetration = json::array();
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::numeric_limits<double>::infinity();
        hi[k] = -lo[k];
    }
    std::vector<int> numberOf, denseOfSlot;
    for (int t = 0; t <= rec.steps; ++t) {
        if (t > 0) session.tick(t, rec.inputs);
        const World& w = session.world();
        const std::vector<BodyId> ids = w.bodyIds();
        const int nb = int(ids.size());
        numberOf.assign(std::size_t(nb), -1);
        denseOfSlot.assign(0, 0);
        for (int d = 0; d < nb; ++d) {
            const int number = session.bodyNumber(ids[std::size_t(d)]);
            numberOf[std::size_t(d)] = number;
            if (denseOfSlot.size() < ids[std::size_t(d)].index1 + 1u) denseOfSlot.resize(ids[std::size_t(d)].index1 + 1u, -1);
            denseOfSlot[ids[std::size_t(d)].index1] = d;
            if (number >= cap.bodyCount) {  // a new body number: its shapes, once
                cap.bodyCount = number + 1;
                while (int(cap.bodies.size()) < cap.bodyCount) cap.bodies.push_back(nullptr);
            }
            if (number >= 0 && cap.bodies[std::size_t(number)].is_null())
                cap.bodies[std::size_t(number)] = dim.bodyJson(w, ids[std::size_t(d)], cap.geometry);
        }
        Frame f;
        f.poses.assign(std::size_t(cap.bodyCount) * V::kPose, std::numeric_limits<float>::quiet_NaN());
        f.islands.assign(std::size_t(cap.bodyCount), 0xFFFF);
        std::vector<std::uint8_t> joins(std::size_t(nb), 0);
        for (int d = 0; d < nb; ++d) {
            const int number = numberOf[std::size_t(d)];
            if (number < 0) continue;
            V::pose(w, ids[std::size_t(d)], &f.poses[std::size_t(number) * V::kPose]);
            joins[std::size_t(d)] = V::isDynamic(w, ids[std::size_t(d)]) ? 1 : 0;
            if (!V::isStatic(w, ids[std::size_t(d)]))
                for (int k = 0; k < V::kDim; ++k) {
                    lo[k] = std::min(lo[k], double(f.poses[std::size_t(number) * V::kPose + std::size_t(k)]));
                    hi[k] = std::max(hi[k], double(f.poses[std::size_t(number) * V::kPose + std::size_t(k)]));
                }
        }
        // Contacts and the islands they make (the step's rule: dynamic bodies joined by contact points).
        cap.contactStart.push_back(std::uint32_t(cap.contacts.size() / V::kContact));
        std::vector<IslandEdge> edges;
        for (const auto& c : w.contacts()) {
            const int da = c.a.index1 < denseOfSlot.size() ? denseOfSlot[c.a.index1] : -1;
            const int db = c.b.index1 < denseOfSlot.size() ? denseOfSlot[c.b.index1] : -1;
            if (da < 0 || db < 0) continue;
            edges.push_back({da, db});
            float v[V::kContact];
            V::contact(c, v);
            cap.contacts.insert(cap.contacts.end(), v, v + V::kContact);
            cap.contactBodies.push_back(std::uint16_t(numberOf[std::size_t(da)]));
            cap.contactBodies.push_back(std::uint16_t(numberOf[std::size_t(db)]));
        }
        const Islands islands = buildIslands(nb, joins, edges);
        for (int k = 0; k < islands.count(); ++k) {
            int smallest = 0x7FFF;
            bool asleep = true;
            for (int i = islands.bodyStart[std::size_t(k)]; i < islands.bodyStart[std::size_t(k) + 1]; ++i) {
                const int d = islands.bodies[std::size_t(i)];
                smallest = std::min(smallest, numberOf[std::size_t(d)]);
                asleep = asleep && !V::awake(w, ids[std::size_t(d)]);
            }
            for (int i = islands.bodyStart[std::size_t(k)]; i < islands.bodyStart[std::size_t(k) + 1]; ++i) {
                const int number = numberOf[std::size_t(islands.bodies[std::size_t(i)])];
                if (number >= 0) f.islands[std::size_t(number)] = std::uint16_t(smallest | (asleep ? 0x8000 : 0));
            }
        }
        frames.push_back(std::move(f));
        cap.hashes.push_back(replay::hexHash(w.stateHash()));
        cap.recordedHashes.push_back(replay::hexHash(rec.hashes[std::size_t(t)]));
        const StepStats& s = w.stats();
        pivots.push_back(t > 0 ? s.pivots : 0);
        work.push_back(t > 0 ? s.work : 0);
        contacts.push_back(w.contacts().size());
        islandCount.push_back(islands.count());
        awakeIslands.push_back(t > 0 ? s.awakeIslands : 0);
        penetration.push_back(float(t > 0 ? s.maxPenetration : 0.0));
    }
    cap.contactStart.push_back(std::uint32_t(cap.contacts.size() / V::kContact));
    // Frames captured before a body existed are shorter: pad them to the final body count.
    cap.poses.reserve(frames.size() * std::size_t(cap.bodyCount) * V::kPose);
    for (Frame& f : frames) {
        f.poses.resize(std::size_t(cap.bodyCount) * V::kPose, std::numeric_limits<float>::quiet_NaN());
        f.islands.resize(std::size_t(cap.bodyCount), 0xFFFF);
        cap.poses.insert(cap.poses.end(), f.poses.begin(), f.poses.end());
        cap.islands.insert(cap.islands.end(), f.islands.begin(), f.islands.end());
    }
    for (int k = 0; k < 3; ++k) {
        cap.bounds[k] = std::isfinite(lo[k]) ? lo[k] : 0.0;
        cap.bounds[3 + k] = std::isfinite(hi[k]) ? hi[k] : 0.0;
    }
    cap.stats = {{"pivots", pivots}, {"work", work}, {"contacts", contacts}, {"islands", islandCount},
                 {"awake_islands", awakeIslands}, {"max_penetration", penetration}};
    return cap;
}

}  // namespace

Capture captureRecording(const replay::Recording& rec) {
    return replay::sceneDimension(rec.scene) == 3 ? captureWith<Dim3View>(rec) : captureWith<Dim2View>(rec);
}

}  // namespace unison::view
