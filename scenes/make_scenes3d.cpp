// scenes/make_scenes3d.cpp — see make_scenes3d.h.
#include "make_scenes3d.h"

#include "det_math.h"
#include "obj_mesh.h"

namespace unison::scenes {
namespace {

using nlohmann::json;

json sceneHeader(bool sleep) {
    return json{{"dimension", 3}, {"gravity", {0.0, -10.0, 0.0}}, {"hz", 60}, {"sleep", sleep}, {"bodies", json::array()}};
}

json groundBody() {
    return json{{"type", "static"},
                {"shapes", {{{"type", "plane"}, {"normal", {0.0, 1.0, 0.0}}, {"offset", 0.0}, {"friction", 0.6}}}}};
}

json boxShape(double hx, double hy, double hz, double friction, double restitution = 0.0) {
    return json{{"type", "box"}, {"half_extents", {hx, hy, hz}}, {"density", 1.0}, {"friction", friction},
                {"restitution", restitution}};
}

// Rotation by angle about a coordinate axis (0 x, 1 y, 2 z) as [w, x, y, z].
json axisQuat(int axis, double angle) {
    double s = 0.0, c = 1.0;
    dmath::sincos(0.5 * angle, &s, &c);
    json q = {c, 0.0, 0.0, 0.0};
    q[std::size_t(axis + 1)] = s;
    return q;
}

json dynamicBody(double x, double y, double z, const json& shape, const json& orientation = {1.0, 0.0, 0.0, 0.0}) {
    return json{{"type", "dynamic"}, {"position", {x, y, z}}, {"orientation", orientation}, {"shapes", {shape}}};
}

// A static box tilted by angle about z whose top surface passes through (x, y, 0): half size (hx, hy, hz).
json rampBody(double x, double y, double angle, double hx, double hy, double hz, double friction) {
    double s = 0.0, c = 1.0;
    dmath::sincos(angle, &s, &c);
    // The top-face normal of the turned box is (-s, c, 0); its centre sits hy below the surface along it.
    return json{{"type", "static"},
                {"position", {x + s * hy, y - c * hy, 0.0}},
                {"orientation", axisQuat(2, angle)},
                {"shapes", {boxShape(hx, hy, hz, friction)}}};
}

// The pen of the box piles: 4 static walls (boxes 0.2 m thick, 4 m high, friction 0.6) around a 3.6 m square
// centred on the origin, all shapes of one static body.
json penBody() {
    const double half = 1.8, wall = 0.1, height = 2.0;
    json pen = {{"type", "static"}, {"shapes", json::array()}};
    for (int side = 0; side < 4; ++side) {
        const double sgn = side % 2 == 0 ? -1.0 : 1.0;
        json wallShape = side < 2 ? boxShape(wall, height, half + 2.0 * wall, 0.6) : boxShape(half, height, wall, 0.6);
        wallShape["center"] = side < 2 ? json{sgn * (half + wall), height, 0.0} : json{0.0, height, sgn * (half + wall)};
        pen["shapes"].push_back(wallShape);
    }
    return pen;
}

}  // namespace

json boxStack3Scene(int count, bool sleep) {
    json scene = sceneHeader(sleep);
    scene["bodies"].push_back(groundBody());
    for (int i = 0; i < count; ++i) scene["bodies"].push_back(dynamicBody(0.0, 0.5 + 1.05 * i, 0.0, boxShape(0.5, 0.5, 0.5, 0.6)));
    return scene;
}

json boxPile3Scene(int count, bool tumble, bool sleep) {
    json scene = sceneHeader(sleep);
    scene["bodies"].push_back(groundBody());
    scene["bodies"].push_back(penBody());
    for (int i = 0; i < count; ++i) {
        const int layer = i / 25, ix = i % 5, iz = (i / 5) % 5;
        const double shift = layer % 2 == 1 ? 0.1 : 0.0;
        // Tumbling: tilted about x by 0.3 rad, so cubes land on an edge and topple into a heap; spun about y by
        // 0.1 rad per layer either way.
        double s = 0.0, c = 1.0;
        if (tumble) dmath::sincos(0.15, &s, &c);
        const json tilt = {c, s, 0.0, 0.0};
        const json spin = axisQuat(1, 0.1 * layer);
        const double qw = spin[0], qy = spin[2], tw = tilt[0], tx = tilt[1];
        const json q = {qw * tw, qw * tx, qy * tw, -qy * tx};  // spin * tilt
        scene["bodies"].push_back(dynamicBody(-1.3 + 0.65 * ix + shift, 0.4 + 0.75 * layer, -1.3 + 0.65 * iz + shift,
                                              boxShape(0.25, 0.25, 0.25, 0.6), q));
    }
    return scene;
}

json dropHeap3Scene(int count, bool sleep) {
    json scene = sceneHeader(sleep);
    scene["bodies"].push_back(groundBody());
    scene["bodies"].push_back(penBody());
    const double tilt = 0.3;
    double st = 0.0, ct = 1.0;
    dmath::sincos(0.5 * tilt, &st, &ct);
    for (int i = 0; i < count; ++i) {
        const int layer = i / 25, ix = i % 5, iz = (i / 5) % 5;
        const double shift = layer % 2 == 1 ? 0.1 : 0.0;
        double sa = 0.0, ca = 1.0;
        dmath::sincos(0.7 + 1.1 * i, &sa, &ca);
        const json q = {ct, st * ca, 0.0, st * sa};  // 0.3 rad about (cos a, 0, sin a)
        scene["bodies"].push_back(dynamicBody(-1.3 + 0.65 * ix + shift, 0.4 + 2.0 * layer, -1.3 + 0.65 * iz + shift,
                                              boxShape(0.25, 0.25, 0.25, 0.6), q));
    }
    return scene;
}

json spheres3Scene(bool sleep) {
    json scene = sceneHeader(sleep);
    scene["restitution_threshold"] = 0.0;
    scene["bodies"].push_back(groundBody());
    for (int k = 0; k < 5; ++k) {
        const json ball = {{"type", "sphere"}, {"radius", 0.5}, {"density", 1.0}, {"friction", 0.6}, {"restitution", k / 4.0}};
        scene["bodies"].push_back(dynamicBody(-4.0 + 2.0 * k, 4.5, 0.0, ball));
    }
    return scene;
}

json ramp3Scene(double angleRad, double mu, bool sleep) {
    json scene = sceneHeader(sleep);
    scene["bodies"].push_back(groundBody());
    scene["bodies"].push_back(rampBody(0.0, 4.0, angleRad, 10.0, 0.5, 5.0, 1.0));
    double s = 0.0, c = 1.0;
    dmath::sincos(angleRad, &s, &c);
    // Cube centre 0.25 above the surface along its normal (-s, c, 0), touching (1 mm overlap) so it starts at rest.
    const double lift = 0.25 - 0.001;
    scene["bodies"].push_back(dynamicBody(-s * lift, 4.0 + c * lift, 0.0, boxShape(0.25, 0.25, 0.25, mu * mu), axisQuat(2, angleRad)));
    return scene;
}

json bunnies3Scene(const std::string& objPath, double scale, int bunnies, bool sleep) {
    json scene = sceneHeader(sleep);
    scene["bodies"].push_back(groundBody());
    const double angle = 0.35;
    scene["bodies"].push_back(rampBody(-1.0, 2.0, -angle, 1.6, 0.1, 1.0, 0.2));  // upper ramp, falls to the right
    scene["bodies"].push_back(rampBody(1.4, 0.9, angle, 1.6, 0.1, 1.0, 0.2));   // lower ramp, falls to the left
    json mesh = inlineMeshKeys(readObj(objPath, scale));
    mesh.update(json{{"type", "mesh"}, {"density", 1.0}, {"friction", 0.5}, {"restitution", 0.1}});
    for (int b = 0; b < bunnies; ++b) {
        scene["bodies"].push_back(dynamicBody(-1.8 + 0.7 * b, 3.0 + 0.6 * b, -0.2 + 0.3 * b, mesh, axisQuat(1, 0.6 * b - 0.3)));
    }
    return scene;
}

}  // namespace unison::scenes
