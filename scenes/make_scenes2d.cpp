// scenes/make_scenes2d.cpp — the shared 2D scene generators (see make_scenes2d.h).
//
// Positions are computed as start + index * step rather than by repeated addition, so every coordinate has at most
// two roundings; for the testbed sizes (half size 0.5) all of them are multiples of 1/16 and exact in binary,
// which is also what Box2D's float copy of the scene sees.
#include "make_scenes2d.h"

#include "det_math.h"

#include <cmath>

namespace unison::scenes {
namespace {

using nlohmann::json;

json vec(double x, double y) { return json::array({x, y}); }

json header(bool sleep) {
    json scene;
    scene["dimension"] = 2;
    scene["gravity"] = vec(0.0, -10.0);
    scene["hz"] = 60;
    scene["sleep"] = sleep;
    scene["bodies"] = json::array();
    return scene;
}

json segmentShape(double x1, double y1, double x2, double y2, double friction) {
    return {{"type", "segment"}, {"points", json::array({vec(x1, y1), vec(x2, y2)})}, {"friction", friction}};
}

json staticBody(json shapes) {
    return {{"type", "static"}, {"position", vec(0.0, 0.0)}, {"shapes", std::move(shapes)}};
}

json dynamicBody(double x, double y, json shape) {
    return {{"type", "dynamic"}, {"position", vec(x, y)}, {"shapes", json::array({std::move(shape)})}};
}

json boxShape(double halfSize, double density, double friction) {
    return {{"type", "box"}, {"half_extents", vec(halfSize, halfSize)}, {"density", density}, {"friction", friction}};
}

json circleShape(double radius, double density, double friction, double restitution) {
    return {{"type", "circle"}, {"radius", radius}, {"density", density}, {"friction", friction},
            {"restitution", restitution}};
}

// Appends the testbed pyramid whose first box is at (x0, y0), in the testbed's order (rows bottom-up, each left
// to right). `scale` = halfSize / 0.5.
void addPyramid(json& bodies, int rows, double halfSize, double x0, double y0) {
    const double scale = halfSize / 0.5;
    const double rowDx = 0.5625 * scale, rowDy = 1.25 * scale, boxDx = 1.125 * scale;
    for (int i = 0; i < rows; ++i) {
        const double rowX = x0 + i * rowDx, rowY = y0 + i * rowDy;
        for (int j = 0; j < rows - i; ++j) bodies.push_back(dynamicBody(rowX + j * boxDx, rowY, boxShape(halfSize, 5.0, 0.6)));
    }
}

json groundBody() { return staticBody(json::array({segmentShape(-40.0, 0.0, 40.0, 0.0, 0.6)})); }

}  // namespace

json pyramidScene(int rows, double halfSize, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    bodies.push_back(groundBody());
    const double scale = halfSize / 0.5;
    addPyramid(bodies, rows, halfSize, -7.0 * scale, 0.75 * scale);
    return scene;
}

json manyPyramidsScene(int count, int rows, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    // A base of `rows` boxes spans (rows - 1) * 1.125 + 1 m; the pitch leaves gap = 2.125 m between bases, and the
    // row of bases, count * pitch - gap wide, is centred on x = 0 (its first box centre is half a box further in).
    const double pitch = rows * 1.125 + 2.0, gap = 2.125;
    const double firstX = -0.5 * (count * pitch - gap) + 0.5;
    const double halfGround = 0.5 * count * pitch + 10.0;
    bodies.push_back(staticBody(json::array({segmentShape(-halfGround, 0.0, halfGround, 0.0, 0.6)})));
    for (int k = 0; k < count; ++k) addPyramid(bodies, rows, 0.5, firstX + k * pitch, 0.75);
    return scene;
}

json fallingCirclesScene(int count, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    const double radius = 0.25, spacing = 0.75;
    int columns = 1;
    while (columns * columns < count) ++columns;
    const int rows = (count + columns - 1) / columns;
    // Circle centres span x in [0, (columns - 1) * spacing + spacing / 2] before centring on x = 0.
    const double span = (columns - 1) * spacing + 0.5 * spacing;
    const double left = -0.5 * span;
    const double wall = 0.5 * span + radius + 0.5;
    const double top = 1.0 + (rows - 1) * spacing + 2.0;
    bodies.push_back(staticBody(json::array({segmentShape(-wall, 0.0, wall, 0.0, 0.6),
                                             segmentShape(-wall, 0.0, -wall, top, 0.6),
                                             segmentShape(wall, 0.0, wall, top, 0.6)})));
    for (int i = 0; i < count; ++i) {
        const int row = i / columns, column = i % columns;
        const double x = left + column * spacing + (row % 2 == 1 ? 0.5 * spacing : 0.0);
        bodies.push_back(dynamicBody(x, 1.0 + row * spacing, circleShape(radius, 1.0, 0.6, 0.0)));
    }
    return scene;
}

json scatteredCirclesScene(int count, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    const double half = 0.5 * (count - 1);
    bodies.push_back(staticBody(json::array({segmentShape(-half - 5.0, 0.0, half + 5.0, 0.0, 0.6)})));
    for (int i = 0; i < count; ++i)
        bodies.push_back(dynamicBody(i - half, 1.0 + 0.25 * (i % 8), circleShape(0.25, 1.0, 0.6, 0.0)));
    return scene;
}

json stackScene(int count, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    bodies.push_back(groundBody());
    // (50 + 105 i) / 100 is one correctly rounded division: the double nearest 0.5 + 1.05 i, as a file would hold it.
    for (int i = 0; i < count; ++i) bodies.push_back(dynamicBody(0.0, (50.0 + 105.0 * i) / 100.0, boxShape(0.5, 1.0, 0.6)));
    return scene;
}

json restitutionRowScene(bool sleep) {
    json scene = header(sleep);
    scene["restitution_threshold"] = 0.0;
    json& bodies = scene["bodies"];
    bodies.push_back(groundBody());
    for (int k = 0; k <= 6; ++k) bodies.push_back(dynamicBody(-6.0 + 2.0 * k, 5.0, circleShape(0.5, 1.0, 0.6, k / 6.0)));
    return scene;
}

json rampScene(double angleRad, double mu, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    double s = 0.0, c = 1.0;
    dmath::sincos(angleRad, &s, &c);
    const double length = 10.0, halfSize = 0.5;
    bodies.push_back(staticBody(json::array({segmentShape(0.0, 0.0, length * c, length * s, 1.0),
                                             segmentShape(-40.0, 0.0, 40.0, 0.0, 1.0)})));
    // Middle of the ramp, lifted by the half size along the ramp's normal (-s, c): the bottom face lies on it.
    const double along = 0.5 * length;
    json box = dynamicBody(along * c - halfSize * s, along * s + halfSize * c, boxShape(halfSize, 1.0, mu * mu));
    box["angle"] = angleRad;
    bodies.push_back(std::move(box));
    return scene;
}

}  // namespace unison::scenes
