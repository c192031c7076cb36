/* unison/unison.h — the C API of Unison (C99): deterministic 2D and 3D rigid-body worlds for networked games.
 *
 * Conventions:
 *  - Worlds and bodies are named by small value ids with generations; a destroyed world's or body's id stays
 *    invalid even when its slot is reused. A zero-initialised id is the null id.
 *  - Every function that can fail returns a unisonError. On any error nothing changes (no world, body or output
 *    is written except the size a buffer needs); unisonLastErrorMessage() then describes the failure (per thread).
 *  - Definitions start from the unisonDefault...() functions; shapes from the unisonMake...() helpers.
 *  - Arrays and byte buffers: pass (NULL, 0) to learn the size (the call succeeds); a buffer smaller than the
 *    answer gets nothing and UNISON_ERROR_BUFFER_TOO_SMALL, with the size written to the count.
 *  - Units: metres, seconds, kilograms, radians; impulses in N s. y is up.
 *  - Results are bit-identical on every machine for the same calls in the same order (see docs/determinism.md).
 *    A world can only be created when the floating-point environment allows that (UNISON_ERROR_FLOATING_POINT).
 *  - Functions on one world must not run concurrently; different worlds may be used from different threads.
 */
#ifndef UNISON_UNISON_H
#define UNISON_UNISON_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32) && defined(UNISON_SHARED)
#if defined(UNISON_BUILDING)
#define UNISON_API __declspec(dllexport)
#else
#define UNISON_API __declspec(dllimport)
#endif
#elif defined(__GNUC__)
#define UNISON_API __attribute__((visibility("default")))
#else
#define UNISON_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- errors and version ------------------------------------------------------------------------------------- */

/** Outcome of a call. */
typedef enum unisonError {
    UNISON_OK = 0,
    UNISON_ERROR_NULL_POINTER = 1,      /**< a required pointer argument is NULL */
    UNISON_ERROR_INVALID_ARGUMENT = 2,  /**< NaN or infinite number, value out of range, invalid shape */
    UNISON_ERROR_INVALID_WORLD = 3,     /**< null, stale or destroyed world id */
    UNISON_ERROR_INVALID_BODY = 4,      /**< null, stale or destroyed body id */
    UNISON_ERROR_WRONG_DIMENSION = 5,   /**< a 2D function on a 3D world, or the reverse */
    UNISON_ERROR_BUFFER_TOO_SMALL = 6,  /**< the answer does not fit; its size was written */
    UNISON_ERROR_BAD_DATA = 7,          /**< a snapshot, compact state or recording was refused */
    UNISON_ERROR_CAPACITY = 8,          /**< too many worlds or bodies */
    UNISON_ERROR_FLOATING_POINT = 9,    /**< flush-to-zero, another rounding mode or excess precision is active */
    UNISON_ERROR_INTERNAL = 10,         /**< an unexpected failure inside the library (out of memory) */
    UNISON_ERROR_WORLD_FAULT = 11,      /**< the world's state stopped being finite: it does not step until restored */
    UNISON_ERROR_MAX_ENUM = 0x7fffffff  /**< never returned: makes every int a value of the type (C callers may pass any) */
} unisonError;

/** Stable lower-case name of an error code ("ok", "invalid_argument", ...). */
UNISON_API const char* unisonErrorName(unisonError error);
/** Message of the calling thread's last failed call ("" before any failure). Valid until that thread's next call. */
UNISON_API const char* unisonLastErrorMessage(void);

/** Library version. */
typedef struct unisonVersion {
    int major, minor, patch;
} unisonVersion;
/** The version of the linked library. */
UNISON_API unisonVersion unisonGetVersion(void);

/* ---- value types -------------------------------------------------------------------------------------------- */

/** A 2D vector (m, m/s or a direction). */
typedef struct unisonVec2 {
    double x, y;
} unisonVec2;
/** A 3D vector (m, m/s, rad/s or a direction). */
typedef struct unisonVec3 {
    double x, y, z;
} unisonVec3;
/** A unit quaternion w + xi + yj + zk. */
typedef struct unisonQuat {
    double w, x, y, z;
} unisonQuat;

/** A world: slot + 1 and generation (0, 0 is null). */
typedef struct unisonWorldId {
    uint32_t index1, generation;
} unisonWorldId;
/** A body of a world: slot + 1 and generation (0, 0 is null). */
typedef struct unisonBodyId {
    uint32_t index1, generation;
} unisonBodyId;

/** Static bodies never move; kinematic bodies move with their velocity (infinite mass); dynamic bodies respond to
 *  gravity, contacts and impulses. */
typedef enum unisonBodyType {
    UNISON_BODY_STATIC = 0,
    UNISON_BODY_KINEMATIC = 1,
    UNISON_BODY_DYNAMIC = 2,
    UNISON_BODY_MAX_ENUM = 0x7fffffff /**< not a body type: makes every int a value of the type (refused) */
} unisonBodyType;

/** Two bodies that started (begin) or stopped (end) touching with overlap during the last step. */
typedef struct unisonTouchEvent {
    unisonBodyId a, b;
} unisonTouchEvent;

/** One shape of one body (the answer of an overlap query). */
typedef struct unisonShapeRef {
    unisonBodyId body;
    int shape; /**< index of the shape in the body, in creation order */
} unisonShapeRef;

/** Counts of the last step. */
typedef struct unisonStepInfo {
    int islands, awakeIslands, contacts, pivots;
    uint64_t work;                 /**< deterministic work units the step spent */
    uint64_t budget;               /**< the step's budget in work units (0: unlimited) */
    uint64_t minimumWork;          /**< what no budget can cut; work <= max(budget, minimumWork) + overrun */
    uint64_t overrun;              /**< work of exact attempts beyond their share */
    int exactIslands;              /**< islands with contacts solved exactly */
    int approximateIslands;        /**< islands given the bounded approximation (budget, or a failed 3D solve) */
    int failedIslands;             /**< failed friction solves (then 2D: the frictionless LCP; 3D: the approximation) */
    int unsolvedIslands;           /**< islands that got no impulse */
    double maxResidual;            /**< largest complementarity residual of an exact answer applied */
    double maxApproximateResidual; /**< largest residual of an approximate island's answer */
    double maxPenetration;         /**< deepest overlap among touching contacts (m) */
    int activeSetIslands;          /**< of exactIslands, answered by the 2D active-set path (not Lemke) */
} unisonStepInfo;

/** Work units of `ms` milliseconds on the reference machine (a fixed constant, never measured at run time). */
UNISON_API uint64_t unisonWorkUnitsFromMilliseconds(double ms);

/* ---- worker threads ------------------------------------------------------------------------------------------ */

/** A task body: processes items [begin, end) on worker `worker` (0 <= worker < workerCount). */
typedef void unisonTaskCallback(int begin, int end, int worker, void* taskContext);
/** Starts `task` over `itemCount` items in ranges of at least `minRange` on the embedding job system; returns a
 *  handle for the finish callback, or NULL when the task already ran to completion. */
typedef void* unisonEnqueueTaskCallback(unisonTaskCallback* task, int itemCount, int minRange, void* taskContext,
                                        void* userContext);
/** Waits until the task of `userTask` (never NULL) has processed every item. */
typedef void unisonFinishTaskCallback(void* userTask, void* userContext);

/** The threads of a world's step: the built-in pool (both callbacks NULL) or an embedding job system. Results are
 *  the same bits for any worker count and job system. */
typedef struct unisonTaskSystem {
    int workerCount;                        /**< >= 1, default 1 (everything on the calling thread) */
    unisonEnqueueTaskCallback* enqueueTask; /**< NULL: the built-in pool */
    unisonFinishTaskCallback* finishTask;   /**< set together with enqueueTask */
    void* userContext;                      /**< passed to both callbacks */
} unisonTaskSystem;

/* ---- 2D definitions ----------------------------------------------------------------------------------------- */

/** 2D world settings (unisonDefaultWorldDef2()). */
typedef struct unisonWorldDef2 {
    unisonVec2 gravity;     /**< m/s^2, default (0, -10) */
    double hz;              /**< steps per second, default 60 */
    int enableSleep;        /**< non-zero: islands at rest for 0.5 s sleep until touched (default 1) */
    uint64_t stepBudget;    /**< work units per step (0 = unlimited, the default); part of the state */
    unisonTaskSystem tasks; /**< worker threads (default: one); not state */
} unisonWorldDef2;

/** How to create a 2D body (unisonDefaultBodyDef2(): dynamic at the origin, at rest). */
typedef struct unisonBodyDef2 {
    unisonBodyType type;
    unisonVec2 position;       /**< body origin (m) */
    double angle;              /**< rad */
    unisonVec2 linearVelocity; /**< m/s */
    double angularVelocity;    /**< rad/s */
} unisonBodyDef2;

/** 2D shape kinds. */
typedef enum unisonShapeType2 {
    UNISON_SHAPE2_CIRCLE = 0,
    UNISON_SHAPE2_BOX = 1,
    UNISON_SHAPE2_POLYGON = 2,
    UNISON_SHAPE2_SEGMENT = 3,
    UNISON_SHAPE2_MAX_ENUM = 0x7fffffff /**< not a shape type: makes every int a value of the type (refused) */
} unisonShapeType2;

/** A 2D shape in body coordinates with its material (start from a unisonMake...2() helper). */
typedef struct unisonShapeDef2 {
    unisonShapeType2 type;
    unisonVec2 center;            /**< circle or box centre (m) */
    double radius;                /**< circle radius (m) */
    unisonVec2 halfExtents;       /**< box half width and height (m) */
    double angle;                 /**< box rotation in the body frame (rad) */
    const unisonVec2* points;     /**< polygon: 3..8 counter-clockwise convex points (read during the call only) */
    int pointCount;               /**< number of polygon points */
    unisonVec2 segmentStart;      /**< segment end points (m) */
    unisonVec2 segmentEnd;
    double density;               /**< kg/m^2, default 1 */
    double friction;              /**< default 0.6; contacts use sqrt(f1 f2) */
    double restitution;           /**< default 0; contacts use max(e1, e2) */
} unisonShapeDef2;

/** A 2D body's state. */
typedef struct unisonBodyState2 {
    unisonBodyType type;
    unisonVec2 position;       /**< body origin (m) */
    double angle;              /**< rad, in [-pi, pi] */
    unisonVec2 center;         /**< world centre of mass (m) */
    unisonVec2 linearVelocity; /**< m/s */
    double angularVelocity;    /**< rad/s */
    double mass;               /**< kg (0 unless dynamic) */
    int awake;                 /**< 0 while asleep */
} unisonBodyState2;

/** A contact point of the last step. */
typedef struct unisonContactPoint2 {
    unisonBodyId a, b;     /**< the normal points from b towards a */
    unisonVec2 point;      /**< midway between the surfaces (m) */
    unisonVec2 normal;     /**< unit normal from b towards a */
    double separation;     /**< gap (m), negative when overlapping */
    double normalImpulse;  /**< N s */
    double tangentImpulse; /**< N s along (-normal.y, normal.x) */
} unisonContactPoint2;

/** A shape hit by a ray. */
typedef struct unisonRayHit2 {
    unisonBodyId body;
    int shape;         /**< index of the shape in the body */
    unisonVec2 point;  /**< where the ray meets the shape (m) */
    unisonVec2 normal; /**< unit surface normal there, against the ray */
    double fraction;   /**< point = origin + fraction * translation, in [0, 1] */
} unisonRayHit2;

/* ---- 3D definitions ----------------------------------------------------------------------------------------- */

/** 3D world settings (unisonDefaultWorldDef3()). */
typedef struct unisonWorldDef3 {
    unisonVec3 gravity;     /**< m/s^2, default (0, -10, 0) */
    double hz;              /**< steps per second, default 60 */
    int enableSleep;        /**< default 1 */
    uint64_t stepBudget;    /**< work units per step (0 = unlimited, the default); part of the state */
    unisonTaskSystem tasks; /**< worker threads (default: one); not state */
} unisonWorldDef3;

/** How to create a 3D body (unisonDefaultBodyDef3(): dynamic at the origin, identity orientation, at rest). */
typedef struct unisonBodyDef3 {
    unisonBodyType type;
    unisonVec3 position;        /**< body origin (m) */
    unisonQuat orientation;     /**< normalised on creation */
    unisonVec3 linearVelocity;  /**< m/s */
    unisonVec3 angularVelocity; /**< rad/s, world axes */
} unisonBodyDef3;

/** 3D shape kinds. */
typedef enum unisonShapeType3 {
    UNISON_SHAPE3_SPHERE = 0,
    UNISON_SHAPE3_BOX = 1,
    UNISON_SHAPE3_HULL = 2,
    UNISON_SHAPE3_PLANE = 3,
    UNISON_SHAPE3_MESH = 4,
    UNISON_SHAPE3_MAX_ENUM = 0x7fffffff /**< not a shape type: makes every int a value of the type (refused) */
} unisonShapeType3;

/** A 3D shape in body coordinates with its material (start from a unisonMake...3() helper). */
typedef struct unisonShapeDef3 {
    unisonShapeType3 type;
    unisonVec3 center;        /**< sphere or box centre (m) */
    double radius;            /**< sphere radius (m) */
    unisonVec3 halfExtents;   /**< box half extents (m) */
    unisonVec3 normal;        /**< plane: solid side normal . x <= offset */
    double offset;            /**< plane offset (m) */
    const unisonVec3* points; /**< hull points (4..256) or mesh vertices (read during the call only) */
    int pointCount;
    const int* triangles;     /**< mesh: 3 vertex indices per triangle, counter-clockwise seen from outside */
    int triangleCount;
    double density;           /**< kg/m^3, default 1 */
    double friction;          /**< default 0.6 */
    double restitution;       /**< default 0 */
} unisonShapeDef3;

/** A 3D body's state. */
typedef struct unisonBodyState3 {
    unisonBodyType type;
    unisonVec3 position;        /**< body origin (m) */
    unisonQuat orientation;     /**< body to world */
    unisonVec3 center;          /**< world centre of mass (m) */
    unisonVec3 linearVelocity;  /**< m/s */
    unisonVec3 angularVelocity; /**< rad/s */
    double mass;                /**< kg (0 unless dynamic) */
    int awake;                  /**< 0 while asleep */
} unisonBodyState3;

/** A contact point of the last step. */
typedef struct unisonContactPoint3 {
    unisonBodyId a, b;
    unisonVec3 point, normal;  /**< midway point (m) and unit normal from b towards a */
    double separation;         /**< m, negative when overlapping */
    double normalImpulse;      /**< N s */
    unisonVec3 tangentImpulse; /**< N s, world frame */
} unisonContactPoint3;

/** A shape hit by a ray. */
typedef struct unisonRayHit3 {
    unisonBodyId body;
    int shape;
    unisonVec3 point, normal;
    double fraction;
} unisonRayHit3;

/* ---- definitions and shapes --------------------------------------------------------------------------------- */

UNISON_API unisonWorldDef2 unisonDefaultWorldDef2(void);
UNISON_API unisonWorldDef3 unisonDefaultWorldDef3(void);
UNISON_API unisonBodyDef2 unisonDefaultBodyDef2(void);
UNISON_API unisonBodyDef3 unisonDefaultBodyDef3(void);
/** A circle of `radius` (m) centred at `center`, default material. */
UNISON_API unisonShapeDef2 unisonMakeCircle2(unisonVec2 center, double radius);
/** A box of half extents (hx, hy) (m) centred at the body origin, default material. */
UNISON_API unisonShapeDef2 unisonMakeBox2(double hx, double hy);
/** A convex polygon of `count` counter-clockwise points (the array is read when the shape is used). */
UNISON_API unisonShapeDef2 unisonMakePolygon2(const unisonVec2* points, int count);
/** A two-sided segment from a to b, for static bodies. */
UNISON_API unisonShapeDef2 unisonMakeSegment2(unisonVec2 a, unisonVec2 b);
/** A sphere of `radius` (m) centred at `center`. */
UNISON_API unisonShapeDef3 unisonMakeSphere3(unisonVec3 center, double radius);
/** A box of half extents h (m) centred at the body origin. */
UNISON_API unisonShapeDef3 unisonMakeBox3(unisonVec3 halfExtents);
/** The convex hull of `count` points. */
UNISON_API unisonShapeDef3 unisonMakeHull3(const unisonVec3* points, int count);
/** The half-space normal . x <= offset, for static bodies. */
UNISON_API unisonShapeDef3 unisonMakePlane3(unisonVec3 normal, double offset);
/** A closed triangle mesh: `vertexCount` vertices, `triangleCount` triangles of 3 indices each. */
UNISON_API unisonShapeDef3 unisonMakeMesh3(const unisonVec3* vertices, int vertexCount, const int* triangles,
                                           int triangleCount);

/* ---- worlds ------------------------------------------------------------------------------------------------- */

/** Creates a 2D world. */
UNISON_API unisonError unisonCreateWorld2(const unisonWorldDef2* def, unisonWorldId* outWorld);
/** Creates a 3D world. */
UNISON_API unisonError unisonCreateWorld3(const unisonWorldDef3* def, unisonWorldId* outWorld);
/** Destroys a world and all its bodies. */
UNISON_API unisonError unisonDestroyWorld(unisonWorldId world);
/** Non-zero when the id names a live world. */
UNISON_API int unisonWorldIsValid(unisonWorldId world);
/** 2 or 3. */
UNISON_API unisonError unisonGetWorldDimension(unisonWorldId world, int* outDimension);
/** Advances the world by 1/hz seconds within its step budget; UNISON_ERROR_WORLD_FAULT (nothing changes) once its
 *  state stopped being finite (unisonGetWorldFault() says where). */
UNISON_API unisonError unisonStep(unisonWorldId world);
/** The same with `budget` work units (0 = unlimited) for this call only; not state (replays use the world's own). */
UNISON_API unisonError unisonStepWithBudget(unisonWorldId world, uint64_t budget);
/** Sets the per-step budget in work units (0 = unlimited); part of the state: every peer must use the same. */
UNISON_API unisonError unisonSetStepBudget(unisonWorldId world, uint64_t budget);
/** The per-step budget in work units. */
UNISON_API unisonError unisonGetStepBudget(unisonWorldId world, uint64_t* outBudget);
/** Sets the threads of the next steps; UNISON_ERROR_INVALID_ARGUMENT for workerCount < 1 or one callback alone. */
UNISON_API unisonError unisonSetTaskSystem(unisonWorldId world, const unisonTaskSystem* tasks);
/** Why the world stopped stepping, as a NUL-terminated message ("" while its state is finite); same buffer
 *  convention as the byte buffers, the size counting the terminating NUL. */
UNISON_API unisonError unisonGetWorldFault(unisonWorldId world, char* buffer, size_t capacity, size_t* outSize);
/** Steps taken since creation (restored with a snapshot). */
UNISON_API unisonError unisonGetStepCount(unisonWorldId world, uint64_t* outSteps);
/** Counts of the last step. */
UNISON_API unisonError unisonGetStepInfo(unisonWorldId world, unisonStepInfo* outInfo);
/** Sets gravity (m/s^2) of a 2D world. */
UNISON_API unisonError unisonSetGravity2(unisonWorldId world, unisonVec2 gravity);
/** Sets gravity (m/s^2) of a 3D world. */
UNISON_API unisonError unisonSetGravity3(unisonWorldId world, unisonVec3 gravity);

/* ---- bodies ------------------------------------------------------------------------------------------------- */

/** Adds a body with `shapeCount` shapes to a 2D world. */
UNISON_API unisonError unisonCreateBody2(unisonWorldId world, const unisonBodyDef2* def, const unisonShapeDef2* shapes,
                                         int shapeCount, unisonBodyId* outBody);
/** Adds a body with `shapeCount` shapes to a 3D world (planes only on static bodies). */
UNISON_API unisonError unisonCreateBody3(unisonWorldId world, const unisonBodyDef3* def, const unisonShapeDef3* shapes,
                                         int shapeCount, unisonBodyId* outBody);
/** Removes a body (its touches end with the next step). */
UNISON_API unisonError unisonDestroyBody(unisonWorldId world, unisonBodyId body);
/** Non-zero when the body is live in a live world. */
UNISON_API int unisonBodyIsValid(unisonWorldId world, unisonBodyId body);
/** Number of live bodies. */
UNISON_API unisonError unisonGetBodyCount(unisonWorldId world, int* outCount);
/** Live bodies in the order the step visits them (array convention above). */
UNISON_API unisonError unisonGetBodyIds(unisonWorldId world, unisonBodyId* out, int capacity, int* outCount);
/** A body's state in a 2D world. */
UNISON_API unisonError unisonGetBodyState2(unisonWorldId world, unisonBodyId body, unisonBodyState2* outState);
/** A body's state in a 3D world. */
UNISON_API unisonError unisonGetBodyState3(unisonWorldId world, unisonBodyId body, unisonBodyState3* outState);
/** Sets a kinematic or dynamic body's velocity (m/s, rad/s) and wakes it. */
UNISON_API unisonError unisonSetBodyVelocity2(unisonWorldId world, unisonBodyId body, unisonVec2 linear,
                                              double angular);
UNISON_API unisonError unisonSetBodyVelocity3(unisonWorldId world, unisonBodyId body, unisonVec3 linear,
                                              unisonVec3 angular);
/** Applies an impulse (N s) at a world point (m) to a dynamic body and wakes it. */
UNISON_API unisonError unisonApplyImpulse2(unisonWorldId world, unisonBodyId body, unisonVec2 impulse,
                                           unisonVec2 point);
UNISON_API unisonError unisonApplyImpulse3(unisonWorldId world, unisonBodyId body, unisonVec3 impulse,
                                           unisonVec3 point);

/* ---- contacts and events of the last step (array convention above) ------------------------------------------- */

UNISON_API unisonError unisonGetContacts2(unisonWorldId world, unisonContactPoint2* out, int capacity, int* outCount);
UNISON_API unisonError unisonGetContacts3(unisonWorldId world, unisonContactPoint3* out, int capacity, int* outCount);
/** Pairs that started touching, sorted. */
UNISON_API unisonError unisonGetBeginTouchEvents(unisonWorldId world, unisonTouchEvent* out, int capacity,
                                                 int* outCount);
/** Pairs that stopped touching, sorted. */
UNISON_API unisonError unisonGetEndTouchEvents(unisonWorldId world, unisonTouchEvent* out, int capacity, int* outCount);

/* ---- state: hash, snapshots, rollback states (buffer convention above) -------------------------------------- */

/** 64-bit hash of everything that affects the future. */
UNISON_API unisonError unisonGetStateHash(unisonWorldId world, uint64_t* outHash);
/** The whole state; restoring it into a world of the same dimension continues bit-identically. */
UNISON_API unisonError unisonSaveSnapshot(unisonWorldId world, uint8_t* buffer, size_t capacity, size_t* outSize);
/** Replaces the world's state with a snapshot (UNISON_ERROR_BAD_DATA and no change when refused). */
UNISON_API unisonError unisonRestoreSnapshot(unisonWorldId world, const uint8_t* data, size_t size);
/** Rollback state: only what a step can change; restorable while the world holds the same bodies. */
UNISON_API unisonError unisonSaveCompactState(unisonWorldId world, uint8_t* buffer, size_t capacity, size_t* outSize);
UNISON_API unisonError unisonRestoreCompactState(unisonWorldId world, const uint8_t* data, size_t size);

/* ---- scene queries (array convention above; answers in a fixed order: fraction, body slot, shape index) -------- */

/** The first shape the segment origin -> origin + translation meets; *outHasHit is 0 when none. */
UNISON_API unisonError unisonRayCastClosest2(unisonWorldId world, unisonVec2 origin, unisonVec2 translation,
                                             unisonRayHit2* outHit, int* outHasHit);
UNISON_API unisonError unisonRayCastClosest3(unisonWorldId world, unisonVec3 origin, unisonVec3 translation,
                                             unisonRayHit3* outHit, int* outHasHit);
/** Every shape the segment meets. */
UNISON_API unisonError unisonRayCastAll2(unisonWorldId world, unisonVec2 origin, unisonVec2 translation,
                                         unisonRayHit2* out, int capacity, int* outCount);
UNISON_API unisonError unisonRayCastAll3(unisonWorldId world, unisonVec3 origin, unisonVec3 translation,
                                         unisonRayHit3* out, int capacity, int* outCount);
/** Every shape whose bounding box overlaps [lower, upper] (a plane's box is unbounded). */
UNISON_API unisonError unisonOverlapAabb2(unisonWorldId world, unisonVec2 lower, unisonVec2 upper, unisonShapeRef* out,
                                          int capacity, int* outCount);
UNISON_API unisonError unisonOverlapAabb3(unisonWorldId world, unisonVec3 lower, unisonVec3 upper, unisonShapeRef* out,
                                          int capacity, int* outCount);
/** Every shape sharing interior points with `shape` placed at `position` (2D: turned by `angle`; 3D: a sphere, box
 *  or hull with `orientation`). */
UNISON_API unisonError unisonOverlapShape2(unisonWorldId world, const unisonShapeDef2* shape, unisonVec2 position,
                                           double angle, unisonShapeRef* out, int capacity, int* outCount);
UNISON_API unisonError unisonOverlapShape3(unisonWorldId world, const unisonShapeDef3* shape, unisonVec3 position,
                                           unisonQuat orientation, unisonShapeRef* out, int capacity, int* outCount);

/* ---- recordings (docs/replay.md) ---------------------------------------------------------------------------- */

/** Bytes allocated by the library; release with unisonFreeBuffer. */
typedef struct unisonBuffer {
    uint8_t* data;
    size_t size;
} unisonBuffer;
/** Releases a buffer's bytes and zeroes it (NULL and an empty buffer are fine). */
UNISON_API void unisonFreeBuffer(unisonBuffer* buffer);

/** Records `steps` ticks of a scene (JSON text) with inputs (JSON text, or NULL for none), snapshots every
 *  `snapshotEvery` ticks, into *outRecording (the .urec bytes). */
UNISON_API unisonError unisonRecord(const char* sceneJson, const char* inputsJson, int steps, int snapshotEvery,
                                    unisonBuffer* outRecording);

/** What verifying a recording found. */
typedef struct unisonVerifyResult {
    int match;               /**< non-zero when every tick's hash matched */
    int ticks;               /**< ticks replayed */
    int firstDesyncTick;     /**< -1 when none */
    uint64_t recordedHash;   /**< at firstDesyncTick */
    uint64_t replayedHash;   /**< at firstDesyncTick */
    int differingFields;     /**< fields that differ at the first snapshot at or after the desync */
    char summary[256];       /**< one line for a person, NUL-terminated (cut to fit) */
} unisonVerifyResult;

/** Replays a recording tick by tick (a desync is a result, not an error; bad bytes are UNISON_ERROR_BAD_DATA). */
UNISON_API unisonError unisonVerifyRecording(const uint8_t* data, size_t size, unisonVerifyResult* outResult);

#ifdef __cplusplus
}
#endif

#endif /* UNISON_UNISON_H */
