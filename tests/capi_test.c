/* tests/capi_test.c — every function of the C API (unison/unison.h) called from C99: worlds and bodies in 2D and
 * 3D with every shape type, stepping, state reads, contacts and touch events, the array and buffer conventions,
 * snapshots and rollback states that continue bit-identically, scene queries, recordings, and bad arguments (null,
 * stale and wrong-dimension ids, NaN, NULL pointers, bad data) that fail with the right code and change nothing.
 * Exit code 0 when every check passed; each failure is printed with its line. */
#include <unison/unison.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond)                                                              \
    do {                                                                         \
        if (!(cond)) {                                                           \
            ++failures;                                                          \
            fprintf(stderr, "%s:%d: CHECK(%s) failed (last error: %s)\n", __FILE__, __LINE__, #cond, \
                    unisonLastErrorMessage());                                   \
        }                                                                        \
    } while (0)

#define CHECK_CODE(call, code) CHECK((call) == (code))

static uint64_t hashOf(unisonWorldId world) {
    uint64_t h = 0;
    CHECK_CODE(unisonGetStateHash(world, &h), UNISON_OK);
    return h;
}

/* The whole snapshot, allocated (size query first). */
static uint8_t* snapshotOf(unisonWorldId world, size_t* size) {
    uint8_t* bytes;
    CHECK_CODE(unisonSaveSnapshot(world, NULL, 0, size), UNISON_OK);
    bytes = (uint8_t*)malloc(*size);
    CHECK_CODE(unisonSaveSnapshot(world, bytes, *size, size), UNISON_OK);
    return bytes;
}

/* Hash and snapshot bytes unchanged since (hash, snap, size). */
static void checkUnchanged(unisonWorldId world, uint64_t hash, const uint8_t* snap, size_t size) {
    size_t now = 0;
    uint8_t* bytes = snapshotOf(world, &now);
    CHECK(hashOf(world) == hash);
    CHECK(now == size && memcmp(bytes, snap, size) == 0);
    free(bytes);
}

static void testErrorsAndVersion(void) {
    int e;
    unisonVersion v = unisonGetVersion();
    CHECK(v.major == 0 && v.minor >= 1);
    for (e = UNISON_OK; e <= UNISON_ERROR_WORLD_FAULT; ++e) CHECK(strcmp(unisonErrorName((unisonError)e), "unknown") != 0);
    CHECK(strcmp(unisonErrorName(UNISON_ERROR_INVALID_BODY), "invalid_body") == 0);
    CHECK(strcmp(unisonErrorName((unisonError)99), "unknown") == 0);
    CHECK(unisonLastErrorMessage() != NULL);
}

static void test2d(void) {
    unisonWorldDef2 def = unisonDefaultWorldDef2();
    unisonWorldId world, stale;
    unisonBodyDef2 groundDef = unisonDefaultBodyDef2(), boxDef = unisonDefaultBodyDef2();
    unisonShapeDef2 ground = unisonMakeSegment2((unisonVec2){-10, 0}, (unisonVec2){10, 0});
    unisonShapeDef2 box = unisonMakeBox2(0.5, 0.5), ball = unisonMakeCircle2((unisonVec2){0, 0}, 0.4);
    const unisonVec2 tri[3] = {{-0.5, 0}, {0.5, 0}, {0, 0.7}};
    unisonShapeDef2 triangle = unisonMakePolygon2(tri, 3);
    unisonBodyId groundId, boxId, ballId, triId, ids[8], staleBody;
    unisonBodyState2 state;
    unisonContactPoint2 contacts[64];
    unisonTouchEvent events[16];
    unisonRayHit2 hit, hits[8];
    unisonShapeRef refs[8];
    unisonStepInfo info;
    int count = -1, dim = 0, hasHit = -1, i, began = 0;
    uint64_t steps = 0, hash;
    uint8_t *snap, *compact, small[4];
    size_t snapSize = 0, compactSize = 0;

    CHECK(def.hz == 60.0 && def.gravity.y == -10.0 && def.enableSleep == 1);
    CHECK_CODE(unisonCreateWorld2(&def, &world), UNISON_OK);
    CHECK(unisonWorldIsValid(world));
    CHECK_CODE(unisonGetWorldDimension(world, &dim), UNISON_OK);
    CHECK(dim == 2);
    groundDef.type = UNISON_BODY_STATIC;
    CHECK_CODE(unisonCreateBody2(world, &groundDef, &ground, 1, &groundId), UNISON_OK);
    boxDef.position = (unisonVec2){0, 0.5};
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &box, 1, &boxId), UNISON_OK);
    boxDef.position = (unisonVec2){0.1, 1.5};
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &ball, 1, &ballId), UNISON_OK);
    boxDef.position = (unisonVec2){3, 0.2};
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &triangle, 1, &triId), UNISON_OK);
    CHECK(unisonBodyIsValid(world, ballId));

    for (i = 0; i < 60; ++i) {
        CHECK_CODE(unisonStep(world), UNISON_OK);
        if (i == 0) { /* the box's weight is carried by the ground: m g dt in total */
            double total = 0.0;
            int k;
            CHECK_CODE(unisonGetContacts2(world, contacts, 64, &count), UNISON_OK);
            for (k = 0; k < count; ++k)
                if (contacts[k].a.index1 == groundId.index1 || contacts[k].b.index1 == groundId.index1)
                    total += contacts[k].normalImpulse;
            CHECK(total > 0.9 * 10.0 / 60.0);
        }
        CHECK_CODE(unisonGetBeginTouchEvents(world, events, 16, &count), UNISON_OK);
        if (count > 0) began = 1;
    }
    CHECK(began);
    CHECK_CODE(unisonGetEndTouchEvents(world, events, 16, &count), UNISON_OK);
    CHECK_CODE(unisonGetStepCount(world, &steps), UNISON_OK);
    CHECK(steps == 60);
    CHECK_CODE(unisonGetStepInfo(world, &info), UNISON_OK);
    CHECK(info.contacts > 0 && info.islands > 0);

    /* State: the box rests on the ground segment, the ball on the box. */
    CHECK_CODE(unisonGetBodyState2(world, boxId, &state), UNISON_OK);
    CHECK(fabs(state.position.y - 0.5) < 0.01 && fabs(state.mass - 1.0) < 1e-12 && state.type == UNISON_BODY_DYNAMIC);
    CHECK_CODE(unisonGetBodyState2(world, ballId, &state), UNISON_OK);
    CHECK(fabs(state.position.y - 1.4) < 0.02);

    /* Arrays: size query, too small, enough. */
    CHECK_CODE(unisonGetContacts2(world, NULL, 0, &count), UNISON_OK);
    CHECK(count == info.contacts);
    CHECK_CODE(unisonGetContacts2(world, contacts, 1, &count), UNISON_ERROR_BUFFER_TOO_SMALL);
    CHECK(count == info.contacts);
    CHECK_CODE(unisonGetContacts2(world, contacts, 64, &count), UNISON_OK);
    for (i = 0; i < count; ++i) {
        CHECK(fabs(contacts[i].normal.x * contacts[i].normal.x + contacts[i].normal.y * contacts[i].normal.y - 1) < 1e-12);
        CHECK(contacts[i].normalImpulse >= 0.0 && contacts[i].separation < 0.03);
    }
    CHECK(info.awakeIslands == 0); /* everything rests and sleeps after a second (impulses are then 0) */
    CHECK_CODE(unisonGetContacts2(world, NULL, 3, &count), UNISON_ERROR_NULL_POINTER);
    CHECK_CODE(unisonGetContacts2(world, contacts, -1, &count), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonGetBodyCount(world, &count), UNISON_OK);
    CHECK(count == 4);
    CHECK_CODE(unisonGetBodyIds(world, ids, 8, &count), UNISON_OK);
    CHECK(count == 4 && ids[1].index1 == boxId.index1 && ids[1].generation == boxId.generation);

    /* Queries. */
    CHECK_CODE(unisonRayCastClosest2(world, (unisonVec2){0, 10}, (unisonVec2){0, -20}, &hit, &hasHit), UNISON_OK);
    CHECK(hasHit == 1 && hit.body.index1 == ballId.index1 && fabs(hit.point.y - 1.8) < 0.02);
    CHECK_CODE(unisonRayCastClosest2(world, (unisonVec2){50, 10}, (unisonVec2){0, 1}, &hit, &hasHit), UNISON_OK);
    CHECK(hasHit == 0);
    CHECK_CODE(unisonRayCastAll2(world, (unisonVec2){0, 10}, (unisonVec2){0, -20}, hits, 8, &count), UNISON_OK);
    CHECK(count == 3 && hits[0].fraction <= hits[1].fraction && hits[2].body.index1 == groundId.index1);
    CHECK_CODE(unisonOverlapAabb2(world, (unisonVec2){2, 0}, (unisonVec2){4, 1}, refs, 8, &count), UNISON_OK);
    CHECK(count == 2); /* the triangle and the ground segment's box */
    CHECK_CODE(unisonOverlapShape2(world, &ball, (unisonVec2){0, 0.5}, 0.0, refs, 8, &count), UNISON_OK);
    CHECK(count == 1 && refs[0].body.index1 == boxId.index1 && refs[0].shape == 0);

    /* Velocities, impulses, gravity. */
    CHECK_CODE(unisonSetBodyVelocity2(world, triId, (unisonVec2){1, 0}, 0.5), UNISON_OK);
    CHECK_CODE(unisonApplyImpulse2(world, triId, (unisonVec2){0, 0.1}, (unisonVec2){3, 0.3}), UNISON_OK);
    CHECK_CODE(unisonGetBodyState2(world, triId, &state), UNISON_OK);
    CHECK(state.linearVelocity.x == 1.0 && state.awake);
    CHECK_CODE(unisonSetGravity2(world, (unisonVec2){0, -9.81}), UNISON_OK);

    /* Snapshot and rollback state: the continuation is bit-identical. */
    snap = snapshotOf(world, &snapSize);
    CHECK_CODE(unisonSaveSnapshot(world, small, sizeof small, &snapSize), UNISON_ERROR_BUFFER_TOO_SMALL);
    CHECK_CODE(unisonSaveCompactState(world, NULL, 0, &compactSize), UNISON_OK);
    compact = (uint8_t*)malloc(compactSize);
    CHECK_CODE(unisonSaveCompactState(world, compact, compactSize, &compactSize), UNISON_OK);
    CHECK(compactSize < snapSize);
    for (i = 0; i < 20; ++i) CHECK_CODE(unisonStep(world), UNISON_OK);
    hash = hashOf(world);
    CHECK_CODE(unisonRestoreCompactState(world, compact, compactSize), UNISON_OK);
    for (i = 0; i < 20; ++i) CHECK_CODE(unisonStep(world), UNISON_OK);
    CHECK(hashOf(world) == hash);
    CHECK_CODE(unisonRestoreSnapshot(world, snap, snapSize), UNISON_OK);
    for (i = 0; i < 20; ++i) CHECK_CODE(unisonStep(world), UNISON_OK);
    CHECK(hashOf(world) == hash);
    free(snap);
    free(compact);

    /* Bad arguments: each fails with its code and changes nothing. */
    snap = snapshotOf(world, &snapSize);
    hash = hashOf(world);
    boxDef.position.x = NAN;
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &box, 1, &ids[0]), UNISON_ERROR_INVALID_ARGUMENT);
    boxDef.position.x = 0;
    box.radius = 0; /* unused by a box: still valid */
    box.halfExtents.x = -1;
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &box, 1, &ids[0]), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonCreateBody2(world, &boxDef, NULL, 1, &ids[0]), UNISON_ERROR_NULL_POINTER);
    CHECK_CODE(unisonCreateBody2(world, NULL, &ball, 1, &ids[0]), UNISON_ERROR_NULL_POINTER);
    triangle.pointCount = 2;
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &triangle, 1, &ids[0]), UNISON_ERROR_INVALID_ARGUMENT);
    triangle.points = NULL;
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &triangle, 1, &ids[0]), UNISON_ERROR_NULL_POINTER);
    boxDef.type = (unisonBodyType)7;
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &ball, 1, &ids[0]), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonSetBodyVelocity2(world, ballId, (unisonVec2){NAN, 0}, 0), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonSetBodyVelocity2(world, groundId, (unisonVec2){1, 0}, 0), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonApplyImpulse2(world, ballId, (unisonVec2){0, INFINITY}, (unisonVec2){0, 0}), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonSetGravity2(world, (unisonVec2){0, NAN}), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonRayCastAll2(world, (unisonVec2){0, 0}, (unisonVec2){0, 0}, hits, 8, &count), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonRayCastClosest2(world, (unisonVec2){NAN, 0}, (unisonVec2){1, 0}, &hit, &hasHit), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonRayCastClosest2(world, (unisonVec2){0, 0}, (unisonVec2){1, 0}, NULL, &hasHit), UNISON_ERROR_NULL_POINTER);
    CHECK_CODE(unisonOverlapAabb2(world, (unisonVec2){1, 1}, (unisonVec2){0, 0}, refs, 8, &count), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonOverlapShape2(world, NULL, (unisonVec2){0, 0}, 0, refs, 8, &count), UNISON_ERROR_NULL_POINTER);
    CHECK_CODE(unisonOverlapShape2(world, &ball, (unisonVec2){0, 0}, NAN, refs, 8, &count), UNISON_ERROR_INVALID_ARGUMENT);
    snap[snapSize / 2] ^= 0x40;
    CHECK_CODE(unisonRestoreSnapshot(world, snap, snapSize), UNISON_ERROR_BAD_DATA);
    snap[snapSize / 2] ^= 0x40;
    CHECK_CODE(unisonRestoreSnapshot(world, NULL, 10), UNISON_ERROR_NULL_POINTER);
    CHECK_CODE(unisonRestoreCompactState(world, small, sizeof small), UNISON_ERROR_BAD_DATA);
    CHECK_CODE(unisonGetStateHash(world, NULL), UNISON_ERROR_NULL_POINTER);
    checkUnchanged(world, hash, snap, snapSize);

    /* Stale body ids. */
    CHECK_CODE(unisonDestroyBody(world, triId), UNISON_OK);
    staleBody = triId;
    CHECK(!unisonBodyIsValid(world, staleBody));
    hash = hashOf(world);
    free(snap);
    snap = snapshotOf(world, &snapSize);
    CHECK_CODE(unisonDestroyBody(world, staleBody), UNISON_ERROR_INVALID_BODY);
    CHECK_CODE(unisonGetBodyState2(world, staleBody, &state), UNISON_ERROR_INVALID_BODY);
    CHECK_CODE(unisonSetBodyVelocity2(world, staleBody, (unisonVec2){1, 0}, 0), UNISON_ERROR_INVALID_BODY);
    CHECK_CODE(unisonApplyImpulse2(world, staleBody, (unisonVec2){1, 0}, (unisonVec2){0, 0}), UNISON_ERROR_INVALID_BODY);
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &ball, 1, &ids[0]), UNISON_ERROR_INVALID_ARGUMENT); /* type 7 still */
    boxDef.type = UNISON_BODY_DYNAMIC;
    CHECK_CODE(unisonCreateBody2(world, &boxDef, &ball, 1, &ids[0]), UNISON_OK); /* reuses the slot */
    CHECK(ids[0].index1 == staleBody.index1 && ids[0].generation != staleBody.generation);
    CHECK(!unisonBodyIsValid(world, staleBody));
    CHECK_CODE(unisonDestroyBody(world, ids[0]), UNISON_OK);

    /* Wrong dimension and stale worlds. */
    {
        unisonWorldDef3 def3 = unisonDefaultWorldDef3();
        unisonWorldId world3;
        unisonBodyState3 state3;
        CHECK_CODE(unisonCreateWorld3(&def3, &world3), UNISON_OK);
        CHECK_CODE(unisonCreateBody2(world3, &boxDef, &ball, 1, &ids[0]), UNISON_ERROR_WRONG_DIMENSION);
        CHECK_CODE(unisonGetBodyState3(world, boxId, &state3), UNISON_ERROR_WRONG_DIMENSION);
        CHECK_CODE(unisonRestoreSnapshot(world3, snap, snapSize), UNISON_ERROR_BAD_DATA); /* a 2D snapshot */
        CHECK_CODE(unisonDestroyWorld(world3), UNISON_OK);
    }
    free(snap);
    stale = world;
    CHECK_CODE(unisonDestroyWorld(world), UNISON_OK);
    CHECK(!unisonWorldIsValid(stale));
    CHECK_CODE(unisonStep(stale), UNISON_ERROR_INVALID_WORLD);
    CHECK_CODE(unisonDestroyWorld(stale), UNISON_ERROR_INVALID_WORLD);
    CHECK_CODE(unisonGetWorldDimension(stale, &dim), UNISON_ERROR_INVALID_WORLD);
    CHECK(!unisonBodyIsValid(stale, boxId));
    CHECK_CODE(unisonCreateWorld2(NULL, &world), UNISON_ERROR_NULL_POINTER);
    def.hz = 0;
    CHECK_CODE(unisonCreateWorld2(&def, &world), UNISON_ERROR_INVALID_ARGUMENT);
}

static void test3d(void) {
    unisonWorldDef3 def = unisonDefaultWorldDef3();
    unisonWorldId world;
    unisonBodyDef3 groundDef = unisonDefaultBodyDef3(), d = unisonDefaultBodyDef3();
    const unisonVec3 hullPts[4] = {{-0.5, 0, -0.5}, {0.5, 0, -0.5}, {0, 0, 0.5}, {0, 0.8, 0}};
    unisonVec3 cube[8];
    const int tris[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                          2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    unisonShapeDef3 plane = unisonMakePlane3((unisonVec3){0, 1, 0}, 0), shapes[4];
    unisonBodyId ids[5];
    unisonBodyState3 state;
    unisonContactPoint3 contacts[64];
    unisonRayHit3 hit, hits[8];
    unisonShapeRef refs[8];
    int i, count = 0, hasHit = 0;
    uint64_t hash;
    uint8_t* snap;
    size_t snapSize = 0;

    for (i = 0; i < 8; ++i) cube[i] = (unisonVec3){(i & 1) ? 0.3 : -0.3, (i & 2) ? 0.3 : -0.3, (i & 4) ? 0.3 : -0.3};
    shapes[0] = unisonMakeBox3((unisonVec3){0.5, 0.5, 0.5});
    shapes[1] = unisonMakeSphere3((unisonVec3){0, 0, 0}, 0.4);
    shapes[2] = unisonMakeHull3(hullPts, 4);
    shapes[3] = unisonMakeMesh3(cube, 8, tris, 12);
    CHECK_CODE(unisonCreateWorld3(&def, &world), UNISON_OK);
    groundDef.type = UNISON_BODY_STATIC;
    CHECK_CODE(unisonCreateBody3(world, &groundDef, &plane, 1, &ids[0]), UNISON_OK);
    for (i = 0; i < 4; ++i) {
        d.position = (unisonVec3){3.0 * i, 1.0, 0};
        CHECK_CODE(unisonCreateBody3(world, &d, &shapes[i], 1, &ids[i + 1]), UNISON_OK);
    }
    for (i = 0; i < 90; ++i) CHECK_CODE(unisonStep(world), UNISON_OK);
    CHECK_CODE(unisonGetBodyState3(world, ids[1], &state), UNISON_OK);
    CHECK(fabs(state.position.y - 0.5) < 0.01 && fabs(state.orientation.w - 1.0) < 1e-6);
    CHECK_CODE(unisonGetBodyState3(world, ids[2], &state), UNISON_OK);
    CHECK(fabs(state.position.y - 0.4) < 0.01);
    CHECK_CODE(unisonGetContacts3(world, contacts, 64, &count), UNISON_OK);
    CHECK(count >= 4 && fabs(contacts[0].normal.y) > 0.99);
    CHECK_CODE(unisonRayCastClosest3(world, (unisonVec3){0, 5, 0}, (unisonVec3){0, -10, 0}, &hit, &hasHit), UNISON_OK);
    CHECK(hasHit && hit.body.index1 == ids[1].index1 && fabs(hit.point.y - 1.0) < 0.01);
    CHECK_CODE(unisonRayCastAll3(world, (unisonVec3){9, 5, 0}, (unisonVec3){0, -10, 0}, hits, 8, &count), UNISON_OK);
    CHECK(count == 2 && hits[0].body.index1 == ids[4].index1 && hits[1].body.index1 == ids[0].index1);
    CHECK_CODE(unisonOverlapAabb3(world, (unisonVec3){2, 0.1, -1}, (unisonVec3){4, 2, 1}, refs, 8, &count), UNISON_OK);
    CHECK(count == 2); /* the sphere and the plane's unbounded box */
    CHECK_CODE(unisonOverlapShape3(world, &shapes[1], (unisonVec3){6, 0.2, 0}, (unisonQuat){1, 0, 0, 0}, refs, 8, &count),
               UNISON_OK);
    CHECK(count == 2); /* the hull and the plane */
    CHECK_CODE(unisonSetBodyVelocity3(world, ids[2], (unisonVec3){0, 0, 1}, (unisonVec3){0, 0, 0}), UNISON_OK);
    CHECK_CODE(unisonApplyImpulse3(world, ids[2], (unisonVec3){0, 1, 0}, (unisonVec3){3, 0.4, 0}), UNISON_OK);
    CHECK_CODE(unisonSetGravity3(world, (unisonVec3){0, -9.81, 0}), UNISON_OK);

    snap = snapshotOf(world, &snapSize);
    hash = hashOf(world);
    d.type = UNISON_BODY_DYNAMIC;
    CHECK_CODE(unisonCreateBody3(world, &d, &plane, 1, &ids[0]), UNISON_ERROR_INVALID_ARGUMENT); /* planes: static */
    shapes[3].triangleCount = 11; /* an open mesh */
    CHECK_CODE(unisonCreateBody3(world, &d, &shapes[3], 1, &ids[0]), UNISON_ERROR_INVALID_ARGUMENT);
    shapes[3].triangles = NULL;
    CHECK_CODE(unisonCreateBody3(world, &d, &shapes[3], 1, &ids[0]), UNISON_ERROR_NULL_POINTER);
    d.orientation = (unisonQuat){0, 0, 0, 0};
    CHECK_CODE(unisonCreateBody3(world, &d, &shapes[1], 1, &ids[0]), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonSetBodyVelocity3(world, ids[2], (unisonVec3){0, NAN, 0}, (unisonVec3){0, 0, 0}),
               UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonApplyImpulse3(world, ids[2], (unisonVec3){0, 1, 0}, (unisonVec3){NAN, 0, 0}),
               UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonSetGravity3(world, (unisonVec3){INFINITY, 0, 0}), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonOverlapShape3(world, &plane, (unisonVec3){0, 0, 0}, (unisonQuat){1, 0, 0, 0}, refs, 8, &count),
               UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonOverlapAabb3(world, (unisonVec3){0, 0, 0}, (unisonVec3){1, NAN, 1}, refs, 8, &count),
               UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonRayCastClosest3(world, (unisonVec3){0, 0, 0}, (unisonVec3){0, 0, 0}, &hit, &hasHit),
               UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonGetContacts2(world, NULL, 0, &count), UNISON_ERROR_WRONG_DIMENSION);
    CHECK_CODE(unisonSetGravity2(world, (unisonVec2){0, 0}), UNISON_ERROR_WRONG_DIMENSION);
    checkUnchanged(world, hash, snap, snapSize);
    free(snap);
    CHECK_CODE(unisonDestroyWorld(world), UNISON_OK);
}

static void testRecording(void) {
    const char* scene =
        "{\"dimension\": 2, \"gravity\": [0, -10], \"hz\": 60, \"bodies\": ["
        "{\"type\": \"static\", \"position\": [0, 0], \"shapes\": [{\"type\": \"segment\", \"points\": [[-5, 0], [5, 0]]}]},"
        "{\"type\": \"dynamic\", \"position\": [0, 2], \"shapes\": [{\"type\": \"box\", \"half_extents\": [0.5, 0.5]}]}]}";
    const char* inputs = "{\"inputs\": [{\"tick\": 5, \"type\": \"apply_impulse\", \"body\": 1, \"impulse\": [1, 0]}]}";
    unisonBuffer rec = {NULL, 0};
    unisonVerifyResult result;
    CHECK_CODE(unisonRecord(scene, inputs, 30, 10, &rec), UNISON_OK);
    CHECK(rec.data != NULL && rec.size > 0);
    CHECK_CODE(unisonVerifyRecording(rec.data, rec.size, &result), UNISON_OK);
    CHECK(result.match && result.ticks == 30 && result.firstDesyncTick == -1);
    CHECK(strcmp(result.summary, "all 30 ticks match") == 0);
    rec.data[rec.size / 2] ^= 1;
    CHECK_CODE(unisonVerifyRecording(rec.data, rec.size, &result), UNISON_ERROR_BAD_DATA);
    unisonFreeBuffer(&rec);
    CHECK(rec.data == NULL && rec.size == 0);
    unisonFreeBuffer(NULL);
    CHECK_CODE(unisonRecord(scene, NULL, 10, 5, &rec), UNISON_OK);
    unisonFreeBuffer(&rec);
    CHECK_CODE(unisonRecord("{", NULL, 10, 5, &rec), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK(strlen(unisonLastErrorMessage()) > 0);
    CHECK_CODE(unisonRecord(NULL, NULL, 10, 5, &rec), UNISON_ERROR_NULL_POINTER);
    CHECK_CODE(unisonVerifyRecording(NULL, 0, &result), UNISON_ERROR_NULL_POINTER);
}

/* A job system of the embedding program: runs each task at once on the calling thread, counting them. */
static int taskCount = 0;
static void* runNow(unisonTaskCallback* task, int itemCount, int minRange, void* taskContext, void* user) {
    int begin;
    (void)user;
    ++taskCount;
    if (minRange < 1) minRange = 1;
    for (begin = 0; begin < itemCount; begin += minRange)
        task(begin, begin + minRange < itemCount ? begin + minRange : itemCount, 0, taskContext);
    return NULL;
}
static void finishNothing(void* userTask, void* user) {
    (void)userTask;
    (void)user;
}

/* Per-step budgets and worker threads: a budgeted world on the built-in pool, on the embedding job system and on
 * one thread give the same hash every step; bad settings are refused and change nothing. */
static void testBudgetAndThreads(void) {
    unisonWorldId worlds[3];
    unisonBodyId id;
    unisonStepInfo info;
    unisonTaskSystem tasks;
    const unisonShapeDef2 ground = unisonMakeSegment2((unisonVec2){-10, 0}, (unisonVec2){20, 0});
    const unisonShapeDef2 box = unisonMakeBox2(0.5, 0.5);
    uint64_t budget = unisonWorkUnitsFromMilliseconds(0.05), stored = 0, hash;
    size_t faultSize = 0;
    char fault[8];
    int w, i, step;
    CHECK(budget > 0 && unisonWorkUnitsFromMilliseconds(0.0) == 0);
    for (w = 0; w < 3; ++w) {
        unisonWorldDef2 def = unisonDefaultWorldDef2();
        unisonBodyDef2 body = unisonDefaultBodyDef2();
        def.stepBudget = budget;
        if (w == 1) def.tasks.workerCount = 2;
        if (w == 2) {
            def.tasks.workerCount = 2;
            def.tasks.enqueueTask = runNow;
            def.tasks.finishTask = finishNothing;
        }
        CHECK_CODE(unisonCreateWorld2(&def, &worlds[w]), UNISON_OK);
        body.type = UNISON_BODY_STATIC;
        CHECK_CODE(unisonCreateBody2(worlds[w], &body, &ground, 1, &id), UNISON_OK);
        body.type = UNISON_BODY_DYNAMIC;
        for (i = 0; i < 80; ++i) { /* 4 towers of 20 boxes: 4 islands, and more bodies than one task's range */
            body.position.x = 3.0 * (i % 4) + 0.01 * (i / 4);
            body.position.y = 0.5 + 1.0 * (i / 4);
            CHECK_CODE(unisonCreateBody2(worlds[w], &body, &box, 1, &id), UNISON_OK);
        }
    }
    for (step = 0; step < 90; ++step) {
        for (w = 0; w < 3; ++w) CHECK_CODE(unisonStep(worlds[w]), UNISON_OK);
        CHECK(hashOf(worlds[1]) == hashOf(worlds[0]) && hashOf(worlds[2]) == hashOf(worlds[0]));
    }
    CHECK(taskCount > 0);
    CHECK_CODE(unisonGetStepInfo(worlds[0], &info), UNISON_OK);
    CHECK(info.budget == budget && info.work <= (budget > info.minimumWork ? budget : info.minimumWork) + info.overrun);
    CHECK_CODE(unisonGetStepBudget(worlds[0], &stored), UNISON_OK);
    CHECK(stored == budget);
    CHECK_CODE(unisonStepWithBudget(worlds[0], 0), UNISON_OK);
    CHECK_CODE(unisonGetStepInfo(worlds[0], &info), UNISON_OK);
    CHECK(info.budget == 0 && info.approximateIslands == 0);
    CHECK_CODE(unisonSetStepBudget(worlds[1], 0), UNISON_OK);
    CHECK_CODE(unisonGetStepBudget(worlds[1], &stored), UNISON_OK);
    CHECK(stored == 0);
    hash = hashOf(worlds[2]);
    tasks.workerCount = 0;
    tasks.enqueueTask = NULL;
    tasks.finishTask = NULL;
    tasks.userContext = NULL;
    CHECK_CODE(unisonSetTaskSystem(worlds[2], &tasks), UNISON_ERROR_INVALID_ARGUMENT);
    tasks.workerCount = 2;
    tasks.finishTask = finishNothing;
    CHECK_CODE(unisonSetTaskSystem(worlds[2], &tasks), UNISON_ERROR_INVALID_ARGUMENT);
    CHECK_CODE(unisonSetTaskSystem(worlds[2], NULL), UNISON_ERROR_NULL_POINTER);
    CHECK(hashOf(worlds[2]) == hash);
    tasks.finishTask = NULL;
    CHECK_CODE(unisonSetTaskSystem(worlds[2], &tasks), UNISON_OK);
    CHECK_CODE(unisonGetWorldFault(worlds[2], NULL, 0, &faultSize), UNISON_OK);
    CHECK(faultSize == 1);
    CHECK_CODE(unisonGetWorldFault(worlds[2], fault, sizeof fault, &faultSize), UNISON_OK);
    CHECK(fault[0] == 0);
    CHECK_CODE(unisonGetStepBudget(worlds[2], NULL), UNISON_ERROR_NULL_POINTER);
    for (w = 0; w < 3; ++w) CHECK_CODE(unisonDestroyWorld(worlds[w]), UNISON_OK);
    CHECK_CODE(unisonStepWithBudget(worlds[0], 1), UNISON_ERROR_INVALID_WORLD);
}

int main(void) {
    testErrorsAndVersion();
    testBudgetAndThreads();
    test2d();
    test3d();
    testRecording();
    if (failures) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("capi: all checks passed\n");
    return 0;
}
