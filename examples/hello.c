/* examples/hello.c — Unison's C API: drop a few boxes on the ground, step two seconds, cast a ray down through
 * the pile and print the state hash (the same on every machine). */
#include <unison/unison.h>

#include <stdio.h>

int main(void) {
    unisonWorldDef2 worldDef = unisonDefaultWorldDef2(); /* gravity (0, -10) m/s^2, 60 steps per second */
    unisonWorldId world;
    if (unisonCreateWorld2(&worldDef, &world) != UNISON_OK) {
        fprintf(stderr, "%s\n", unisonLastErrorMessage());
        return 1;
    }
    unisonBodyDef2 groundDef = unisonDefaultBodyDef2();
    groundDef.type = UNISON_BODY_STATIC;
    unisonShapeDef2 groundShape = unisonMakeSegment2((unisonVec2){-20, 0}, (unisonVec2){20, 0});
    unisonBodyId body;
    unisonCreateBody2(world, &groundDef, &groundShape, 1, &body);

    unisonShapeDef2 box = unisonMakeBox2(0.5, 0.5);
    for (int i = 0; i < 4; ++i) {
        unisonBodyDef2 bodyDef = unisonDefaultBodyDef2(); /* dynamic, at rest */
        bodyDef.position = (unisonVec2){0.1 * i, 0.5 + 1.2 * i};
        unisonCreateBody2(world, &bodyDef, &box, 1, &body);
    }

    for (int step = 0; step < 120; ++step) unisonStep(world);

    unisonRayHit2 hit;
    int hasHit = 0;
    unisonRayCastClosest2(world, (unisonVec2){0, 10}, (unisonVec2){0, -20}, &hit, &hasHit);
    if (hasHit) printf("ray hit body %u at y = %.3f m\n", (unsigned)hit.body.index1, hit.point.y);
    uint64_t hash = 0;
    unisonGetStateHash(world, &hash);
    printf("state hash %016llx\n", (unsigned long long)hash);
    unisonDestroyWorld(world);
    return 0;
}
