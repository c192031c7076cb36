// examples/hello.cpp — Unison's C++ API: drop three boxes and a ball on the ground, step two seconds, cast a ray
// down through the pile and print the state hash (the same on every machine).
#include <unison/world3d.h>

#include <cstdio>

int main() {
    unison::World3D world;  // gravity (0, -10, 0) m/s^2, 60 steps per second

    unison::BodyDef3D ground;
    ground.type = unison::BodyType::staticBody;
    world.createBody(ground, {unison::ShapeDef3D::plane({0, 1, 0}, 0.0)});  // the half-space y <= 0

    for (int i = 0; i < 4; ++i) {
        unison::BodyDef3D body;  // dynamic by default
        body.position = {0.1 * i, 0.5 + 1.2 * i, 0.0};
        const bool ball = i == 3;
        world.createBody(body, {ball ? unison::ShapeDef3D::sphere({}, 0.5) : unison::ShapeDef3D::box({0.5, 0.5, 0.5})});
    }

    for (int step = 0; step < 120; ++step) world.step();

    unison::RayHit3D hit;
    if (world.rayCastClosest({0.0, 10.0, 0.0}, {0.0, -20.0, 0.0}, &hit))
        std::printf("ray hit body %u at y = %.3f m\n", hit.body.index1, hit.point.y);
    std::printf("state hash %016llx after %llu steps\n", static_cast<unsigned long long>(world.stateHash()),
                static_cast<unsigned long long>(world.stepCount()));
    return 0;
}
