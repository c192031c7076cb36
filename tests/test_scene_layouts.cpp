// tests/test_scene_layouts.cpp — layout facts of the generated benchmark scenes (scenes/make_scenes2d, make_scenes3d):
// Box2D v3's benchmark and stacking layouts, the 2000-circle container pile and the 3D drop heap. Each scene is
// read back through the scene readers, every pair of shapes whose boxes meet is run through the narrowphase, and
// the counts, the touching pairs and the deepest overlap are checked against what the layout says.
#include "box2d_peer.h"
#include "collide2d.h"
#include "collide3d.h"
#include "det_math.h"
#include "make_scenes2d.h"
#include "make_scenes3d.h"
#include "scene_json.h"
#include "scene_json3d.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

using namespace unison;
using nlohmann::json;

// Narrowphase survey of a scene at its initial placement: pairs of bodies (at least one dynamic) whose shapes come
// within `margin`.
struct Survey {
    int bodies = 0, dynamicBodies = 0;
    int touchingPairs = 0;               // body pairs with some point of |separation| <= kTouch
    int overlappingPairs = 0;            // body pairs with some point of separation < -kTouch
    double deepest = 0.0;                // most negative separation over all pairs (0 when none overlaps), m
    double deepestDynamic = 0.0;         // the same over pairs of two dynamic bodies
    double nearestApart = 1e300;         // smallest positive separation > kTouch seen, m
};
constexpr double kTouch = 1e-9;  // m: "touching" allows this much rounding of the layout's coordinates

template <class Shape, class Transform, class Box>
struct Placed {
    int body = 0;
    bool dynamic = false;
    Shape shape;
    Transform xf;
    Box box;
};

// Sweep over x of the inflated boxes, then the narrowphase on every pair of shapes of different bodies.
template <class P, class Lower, class Upper, class Overlap, class Collide>
Survey survey(std::vector<P>& placed, int bodies, int dynamicBodies, Lower lower, Upper upper, Overlap overlap,
              Collide collideSeparations) {
    Survey s;
    s.bodies = bodies;
    s.dynamicBodies = dynamicBodies;
    std::sort(placed.begin(), placed.end(), [&](const P& a, const P& b) {
        return lower(a) != lower(b) ? lower(a) < lower(b) : a.body < b.body;
    });
    std::vector<std::pair<int, int>> touching, overlapping;
    for (std::size_t i = 0; i < placed.size(); ++i) {
        for (std::size_t j = i + 1; j < placed.size() && lower(placed[j]) <= upper(placed[i]); ++j) {
            const P& a = placed[i];
            const P& b = placed[j];
            if (a.body == b.body || (!a.dynamic && !b.dynamic) || !overlap(a, b)) continue;
            for (double sep : collideSeparations(a, b)) {
                const std::pair<int, int> key{std::min(a.body, b.body), std::max(a.body, b.body)};
                if (std::fabs(sep) <= kTouch) touching.push_back(key);
                if (sep < -kTouch) overlapping.push_back(key);
                if (sep > kTouch) s.nearestApart = std::min(s.nearestApart, sep);
                s.deepest = std::min(s.deepest, sep);
                if (a.dynamic && b.dynamic) s.deepestDynamic = std::min(s.deepestDynamic, sep);
            }
        }
    }
    for (auto* v : {&touching, &overlapping}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    s.touchingPairs = int(touching.size());
    s.overlappingPairs = int(overlapping.size());
    return s;
}

// The separations of a manifold's points (2D or 3D).
template <class Manifold>
std::vector<double> separationsOf(const Manifold& m) {
    std::vector<double> seps;
    for (int k = 0; k < m.count; ++k) seps.push_back(m.points[std::size_t(k)].separation);
    return seps;
}

Survey survey2(const json& scene, double margin = 0.01) {
    using P = Placed<Shape2, Transform2, Aabb2>;
    std::vector<P> placed;
    const json& bodies = scene.at("bodies");
    int dynamicBodies = 0;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const scenes::BodySpec2 spec = scenes::readBody2(bodies[i], "bodies[" + std::to_string(i) + "]");
        const bool dynamic = spec.def.type == BodyType::dynamicBody;
        dynamicBodies += dynamic ? 1 : 0;
        const Transform2 xf{spec.def.position, makeRot(spec.def.angle)};
        for (const Shape2& shape : spec.shapes) {
            Aabb2 box = computeAabb(shape, xf);
            box.lower = box.lower - Vec2{margin, margin};
            box.upper = box.upper + Vec2{margin, margin};
            placed.push_back({int(i), dynamic, shape, xf, box});
        }
    }
    return survey(
        placed, int(bodies.size()), dynamicBodies, [](const P& p) { return p.box.lower.x; },
        [](const P& p) { return p.box.upper.x; }, [](const P& a, const P& b) { return overlaps(a.box, b.box); },
        [&](const P& a, const P& b) { return separationsOf(collide(a.shape, a.xf, b.shape, b.xf, margin)); });
}

Survey survey3(const json& scene, double margin = 0.01) {
    using P = Placed<Shape3, Transform3, Aabb3>;
    std::vector<P> placed;
    const json& bodies = scene.at("bodies");
    int dynamicBodies = 0;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const scenes::BodySpec3 spec = scenes::readBody3(bodies[i], "bodies[" + std::to_string(i) + "]");
        const bool dynamic = spec.def.type == BodyType::dynamicBody;
        dynamicBodies += dynamic ? 1 : 0;
        Transform3 xf;
        xf.p = spec.def.position;
        xf.r = toMatrix(normalized(spec.def.orientation));
        for (const Shape3& shape : spec.shapes) {
            Aabb3 box = computeAabb(shape, xf);
            box.lower -= Vec3::Constant(margin);
            box.upper += Vec3::Constant(margin);
            placed.push_back({int(i), dynamic, shape, xf, box});
        }
    }
    return survey(
        placed, int(bodies.size()), dynamicBodies, [](const P& p) { return p.box.lower.x(); },
        [](const P& p) { return p.box.upper.x(); },
        [](const P& a, const P& b) {
            return (a.box.lower.array() <= b.box.upper.array()).all() && (b.box.lower.array() <= a.box.upper.array()).all();
        },
        [&](const P& a, const P& b) { return separationsOf(collide(a.shape, a.xf, b.shape, b.xf, margin)); });
}

// Centre of the last body of a 2D scene (its watched body).
Vec2 lastPosition(const json& scene) {
    const json& p = scene.at("bodies").back().at("position");
    return {p[0].get<double>(), p[1].get<double>()};
}

// Touching pairs of a Box2D v3 benchmark pyramid of base b on its ground: b (b - 1) / 2 side by side, b (b - 1)
// resting on two boxes below, b on the ground.
int touchingPairsOfPyramid(int b) { return b * (b - 1) / 2 + b * (b - 1) + b; }

// Both engines' readers accept the scene and agree on its size.
void checkLoads(const json& scene, int bodies) {
    const scenes::LoadedScene2 loaded = scenes::loadScene2(scene, "scene");
    CHECK(int(loaded.bodies.size()) == bodies);
    const bench::Box2dPeer peer(scene, "scene");
    CHECK(peer.bodyCount() == bodies);
}

}  // namespace

TEST_SUITE("scene_layouts") {
    TEST_CASE("large pyramid: 1 m boxes touching side by side and stacked without gaps on a box ground") {
        for (int base : {40, 100}) {
            CAPTURE(base);
            const json scene = scenes::largePyramidScene(base);
            CHECK(scene["sleep"] == false);
            const Survey s = survey2(scene);
            CHECK(s.dynamicBodies == base * (base + 1) / 2);  // 820 and 5050
            CHECK(s.bodies == s.dynamicBodies + 1);
            CHECK(s.overlappingPairs == 0);
            CHECK(s.touchingPairs == touchingPairsOfPyramid(base));
            const Vec2 top = lastPosition(scene);
            CHECK(top.x == 0.0);
            CHECK(top.y == base - 0.5);
            if (base == 40) checkLoads(scene, s.bodies);
        }
    }

    TEST_CASE("many pyramids: rows of base-10 pyramids, each row on its own ground segment 11 m above the last") {
        const json scene = scenes::pyramidGridScene(5, 5);
        const Survey s = survey2(scene);
        CHECK(s.dynamicBodies == 25 * 55);  // 1375
        CHECK(s.overlappingPairs == 0);
        CHECK(s.touchingPairs == 25 * touchingPairsOfPyramid(10));  // no pyramid touches another or the next segment
        CHECK(s.nearestApart >= 1.0 - 1e-12);                       // 1 m between neighbours, below the next segment
        CHECK(scene["bodies"][0]["shapes"].size() == 5);
        const Vec2 top = lastPosition(scene);
        CHECK(top.y == 4 * 11 + 9.5);
        checkLoads(scene, s.bodies);

        const json big = scenes::pyramidGridScene(20, 20);
        CHECK(big["bodies"].size() == 1 + 400 * 55);  // 22000 boxes
        CHECK(big["bodies"][0]["shapes"].size() == 20);
    }

    TEST_CASE("card house: 40 thin cards as in the sample: leaning pairs millimetres apart, bottom ones in the ground") {
        const json scene = scenes::cardHouseScene(5);
        const Survey s = survey2(scene);
        CHECK(s.dynamicBodies == 40);  // 3 Nb - 1 cards on the level of Nb pairs, Nb = 5 .. 1
        // The sample's flat cards, 0.4 m long and 0.35 m apart, overlap their neighbours on the same level by 5 cm
        // through their whole 2 mm thickness: Nb - 2 such pairs on the level of Nb pairs (3 + 2 + 1).
        CHECK(s.deepestDynamic == doctest::Approx(-0.002).epsilon(1e-9));
        // The 10 bottom cards stand 0.18 m high, 0.2 cos 25 + 0.001 sin 25 = 0.18168 m tall from their centre.
        double s25 = 0.0, c25 = 1.0;
        dmath::sincos(25.0 * dmath::kPi / 180.0, &s25, &c25);
        CHECK(s.overlappingPairs == 10 + 6);
        const Survey ground = survey2(scenes::cardHouseScene(1));  // one leaning pair, no flat card
        CHECK(ground.overlappingPairs == 2);
        CHECK(ground.deepest == doctest::Approx(0.18 - 0.2 * c25 - 0.001 * s25).epsilon(1e-6));
        CHECK(ground.deepestDynamic == 0.0);
        CHECK(s.nearestApart > 0.001);  // the closest cards are millimetres apart and land on each other
        for (const json& body : scene["bodies"]) {
            if (body["type"] == "static") continue;
            CHECK(body["shapes"][0]["friction"] == 0.7);
        }
        checkLoads(scene, s.bodies);
        CHECK(ground.bodies == 1 + 2);
    }

    TEST_CASE("arch: 17 stones touching exactly, 4 boxes stacked on the keystone") {
        const json scene = scenes::archScene();
        const Survey s = survey2(scene);
        CHECK(s.dynamicBodies == 21);
        CHECK(s.overlappingPairs == 0);
        // 7 joints up each side, the keystone on both top stones, both bottom stones on the ground, the keystone
        // under the first box (which also meets the outer top corners of the two highest stones, level with the
        // keystone's top) and 3 joints between the boxes.
        CHECK(s.touchingPairs == 7 + 7 + 2 + 2 + 1 + 2 + 3);
        checkLoads(scene, s.bodies);
    }

    TEST_CASE("vertical stack: 12 boxes with no gaps, alternately 1 cm left and right") {
        const json scene = scenes::verticalStackScene(12, 1);
        const Survey s = survey2(scene);
        CHECK(s.dynamicBodies == 12);
        CHECK(s.overlappingPairs == 0);
        CHECK(s.touchingPairs == 12);  // 11 joints and the ground; the wall at x = 10 is 1.5 m away
        CHECK(scene["bodies"][1]["position"][0] == 7.99);
        CHECK(scene["bodies"][2]["position"][0] == 8.01);
        CHECK(scenes::verticalStackScene(10, 3)["bodies"].size() == 31);
        checkLoads(scene, s.bodies);
    }

    TEST_CASE("double domino: 15 dominoes 1 m apart, the first pushed as by the sample's impulse") {
        const json scene = scenes::doubleDominoScene(15);
        const Survey s = survey2(scene);
        CHECK(s.dynamicBodies == 15);
        CHECK(s.overlappingPairs == 0);
        CHECK(s.touchingPairs == 15);  // each on the ground, none touching another
        const json& first = scene["bodies"][1];
        // m = 0.25 kg, I = m (0.25^2 + 1) / 12: v = 0.2 / m, w = -(0.5 * 0.2) / I.
        CHECK(first["linear_velocity"][0] == doctest::Approx(0.8).epsilon(1e-15));
        CHECK(first["angular_velocity"].get<double>() == doctest::Approx(-0.1 / (0.25 * 1.0625 / 12.0)).epsilon(1e-15));
        CHECK(scene["bodies"][2].count("linear_velocity") == 0);
        checkLoads(scene, s.bodies);
    }

    TEST_CASE("2000 circles in a container: nothing overlaps or touches at the start") {
        const json scene = scenes::fallingCirclesScene(2000, false);
        const Survey s = survey2(scene);
        CHECK(s.dynamicBodies == 2000);
        CHECK(s.touchingPairs == 0);
        CHECK(s.overlappingPairs == 0);
        checkLoads(scene, s.bodies);
    }

    TEST_CASE("3D drop heap: 100 cubes tilted 0.3 rad, 4 layers up to 6.4 m, nothing overlapping") {
        const json scene = scenes::dropHeap3Scene(100, false);
        const Survey s = survey3(scene);
        CHECK(s.dynamicBodies == 100);
        CHECK(s.bodies == 102);
        CHECK(s.touchingPairs == 0);
        CHECK(s.overlappingPairs == 0);
        CHECK(scene["bodies"].back()["position"][1] == 6.4);
        // Every cube is turned by 0.3 rad about a horizontal axis: w = cos 0.15, no y component.
        double s15 = 0.0, c15 = 1.0;
        dmath::sincos(0.15, &s15, &c15);
        int corners = 0;
        for (std::size_t i = 2; i < scene["bodies"].size(); ++i) {
            const scenes::BodySpec3 spec = scenes::readBody3(scene["bodies"][i], "cube");
            CHECK(spec.def.orientation.w == c15);
            CHECK(spec.def.orientation.y == 0.0);
            // Lands on a corner when one corner is lowest by more than 1 cm.
            const Mat3 r = toMatrix(spec.def.orientation);
            std::vector<double> heights;
            for (int k = 0; k < 8; ++k) {
                const Vec3 local(k & 1 ? 0.25 : -0.25, k & 2 ? 0.25 : -0.25, k & 4 ? 0.25 : -0.25);
                heights.push_back(mul(r, local).y());
            }
            std::sort(heights.begin(), heights.end());
            corners += heights[1] - heights[0] > 0.01 ? 1 : 0;
        }
        CHECK(corners >= 80);
        const scenes::LoadedScene3 loaded = scenes::loadScene3(scene, "heap");
        CHECK(loaded.bodies.size() == 102);
    }
}
