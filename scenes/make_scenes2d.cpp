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

json rectShape(double hx, double hy, double density, double friction) {
    return {{"type", "box"}, {"half_extents", vec(hx, hy)}, {"density", density}, {"friction", friction}};
}

// A static body at (x, y) holding one box of half extents (hx, hy): Box2D v3's usual ground.
json groundBox(double x, double y, double hx, double hy, double friction) {
    return {{"type", "static"}, {"position", vec(x, y)}, {"shapes", json::array({rectShape(hx, hy, 1.0, friction)})}};
}

// Appends a Box2D v3 benchmark pyramid of 1 m boxes whose first (bottom-left) box is centred at (x0, y0): row i
// holds baseCount - i boxes 1 m apart, starting 0.5 i m further right and i m higher.
void addTouchingPyramid(json& bodies, int baseCount, double x0, double y0) {
    for (int i = 0; i < baseCount; ++i) {
        for (int j = i; j < baseCount; ++j)
            bodies.push_back(dynamicBody(x0 + 0.5 * i + (j - i), y0 + i, rectShape(0.5, 0.5, 1.0, 0.6)));
    }
}

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

// ---- Box2D v3's layouts --------------------------------------------------------------------------------------

json largePyramidScene(int baseCount, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    bodies.push_back(groundBox(0.0, -1.0, 100.0, 1.0, 0.6));
    addTouchingPyramid(bodies, baseCount, 0.5 - 0.5 * baseCount, 0.5);
    return scene;
}

json pyramidGridScene(int rowCount, int columnCount, int baseCount, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    const double pitch = baseCount + 1.0;  // between pyramids of a row and between ground segments (m)
    const double halfWidth = 0.5 * pitch * columnCount;
    json segments = json::array();
    for (int r = 0; r < rowCount; ++r) segments.push_back(segmentShape(-halfWidth, pitch * r, halfWidth, pitch * r, 0.6));
    bodies.push_back(staticBody(std::move(segments)));
    for (int r = 0; r < rowCount; ++r) {
        for (int c = 0; c < columnCount; ++c) addTouchingPyramid(bodies, baseCount, -halfWidth + pitch * c + 1.0, pitch * r + 0.5);
    }
    return scene;
}

json cardHouseScene(int levels, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    const double friction = 0.7, halfThickness = 0.001, halfLength = 0.2;
    const double lean = 25.0 * dmath::kPi / 180.0, flat = 0.5 * dmath::kPi;
    bodies.push_back(groundBox(0.0, -2.0, 40.0, 2.0, friction));
    auto card = [&](double x, double y, double angle) {
        json body = dynamicBody(x, y, rectShape(halfThickness, halfLength, 1.0, friction));
        body["angle"] = angle;
        bodies.push_back(std::move(body));
    };
    for (int level = 0; level < levels; ++level) {
        const int pairs = levels - level;
        // The sample's running sums (y starts at 0.2 - 0.02 and grows by 2 * 0.2 - 0.03; z by 0.175) as products.
        const double y = 0.18 + 0.37 * level;
        for (int i = 0; i < pairs; ++i) {
            const double z = 0.175 * (level + 2 * i);
            if (i != pairs - 1) card(z + 0.25, y + halfLength - 0.015, flat);
            card(z, y, -lean);
            card(z + 0.175, y, lean);
        }
    }
    return scene;
}

json archScene(bool sleep) {
    // The sample's inner (ps1) and outer (ps2) arch curves before its scaling by 0.25 (m).
    static const double inner[9][2] = {{16.0, 0.0},
                                       {14.93803712795643, 5.133601056842984},
                                       {13.79871746027416, 10.24928069555078},
                                       {12.56252963284711, 15.34107019122473},
                                       {11.20040987372525, 20.39856541571217},
                                       {9.66521217819836, 25.40369899225096},
                                       {7.87179930638133, 30.3179337000085},
                                       {5.635199558196225, 35.03820717801641},
                                       {2.405937953536585, 39.09554102558315}};
    static const double outer[9][2] = {{24.0, 0.0},
                                       {22.33619528222415, 6.02299846205841},
                                       {20.54936888969905, 12.00964361211476},
                                       {18.60854610798073, 17.9470321677465},
                                       {16.46769273811807, 23.81367936585418},
                                       {14.05325025774858, 29.57079353071012},
                                       {11.23551045834022, 35.13775818285372},
                                       {7.752568160730571, 40.30450679009583},
                                       {3.016931552701656, 44.28891593799322}};
    const double scale = 0.25, friction = 0.6;
    auto in = [&](int i, double side) { return vec(side * scale * inner[i][0], scale * inner[i][1]); };
    auto out = [&](int i, double side) { return vec(side * scale * outer[i][0], scale * outer[i][1]); };
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    bodies.push_back(staticBody(json::array({segmentShape(-100.0, 0.0, 100.0, 0.0, friction)})));
    auto stone = [&](json vertices) {  // counter-clockwise, in world coordinates
        json shape = {{"type", "polygon"}, {"vertices", std::move(vertices)}, {"density", 1.0}, {"friction", friction}};
        bodies.push_back(dynamicBody(0.0, 0.0, std::move(shape)));
    };
    for (int i = 0; i < 8; ++i) stone(json::array({in(i, 1.0), out(i, 1.0), out(i + 1, 1.0), in(i + 1, 1.0)}));
    for (int i = 0; i < 8; ++i) stone(json::array({out(i, -1.0), in(i, -1.0), in(i + 1, -1.0), out(i + 1, -1.0)}));
    stone(json::array({in(8, 1.0), out(8, 1.0), out(8, -1.0), in(8, -1.0)}));
    const double top = scale * outer[8][1];
    for (int i = 0; i < 4; ++i) bodies.push_back(dynamicBody(0.0, top + 0.5 + i, rectShape(2.0, 0.5, 1.0, friction)));
    return scene;
}

json verticalStackScene(int rows, int columns, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    bodies.push_back(staticBody(json::array({segmentShape(10.0, 0.0, 10.0, 20.0, 0.6),
                                             segmentShape(-30.0, 0.0, 30.0, 0.0, 0.6)})));
    for (int c = 0; c < columns; ++c) {
        for (int i = 0; i < rows; ++i) {
            const double shift = i % 2 == 0 ? -0.01 : 0.01;
            bodies.push_back(dynamicBody(8.0 - 3.0 * c + shift, 0.5 + i, rectShape(0.5, 0.5, 1.0, 0.3)));
        }
    }
    return scene;
}

json doubleDominoScene(int count, bool sleep) {
    json scene = header(sleep);
    json& bodies = scene["bodies"];
    bodies.push_back(groundBox(0.0, -1.0, 100.0, 1.0, 0.6));
    const double hx = 0.125, hy = 0.5, density = 1.0;
    const double mass = density * 4.0 * hx * hy;
    const double inertia = mass * (4.0 * hx * hx + 4.0 * hy * hy) / 12.0;
    const double impulse = 0.2, lever = 0.5;  // (0.2, 0) N s applied 0.5 m above the centre
    for (int i = 0; i < count; ++i) {
        json domino = dynamicBody(-0.5 * count + i, hy, rectShape(hx, hy, density, 0.6));
        if (i == 0) {
            domino["linear_velocity"] = vec(impulse / mass, 0.0);
            domino["angular_velocity"] = -lever * impulse / inertia;  // r x P = (0, lever) x (impulse, 0)
        }
        bodies.push_back(std::move(domino));
    }
    return scene;
}

}  // namespace unison::scenes
