// api/capi.cpp — the C API (unison/unison.h), part 1: errors, version, default definitions and shape helpers, the
// world registry and the world-level calls (step, statistics, gravity, state hash, snapshots, rollback states) and
// recordings. Bodies, contacts, events and queries are in capi_bodies.cpp. Every function checks all its arguments
// before it changes anything and never lets an exception cross into C.
#include "capi_internal.h"

#include <unison/replay.h>
#include <unison/version.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <type_traits>

namespace unison::capi {

namespace {

struct WorldSlot {
    std::uint32_t generation = 0;  // >= 1 once the slot was used
    std::unique_ptr<World2D> w2;
    std::unique_ptr<World3D> w3;
};

constexpr std::size_t kMaxWorlds = 1u << 16;

std::mutex gMutex;
std::vector<WorldSlot> gSlots;
std::vector<std::uint32_t> gFree;  // LIFO, as body slots

thread_local std::string tLastError;

WorldSlot* slotOf(unisonWorldId id) {
    if (id.index1 == 0 || id.index1 > gSlots.size()) return nullptr;
    WorldSlot& s = gSlots[id.index1 - 1];
    return s.generation == id.generation && (s.w2 || s.w3) ? &s : nullptr;
}

// Puts a new world into a free slot; UNISON_ERROR_CAPACITY when all are taken.
unisonError addWorld(std::unique_ptr<World2D> w2, std::unique_ptr<World3D> w3, unisonWorldId* out) {
    const std::lock_guard<std::mutex> lock(gMutex);
    std::uint32_t slot;
    if (!gFree.empty()) {
        slot = gFree.back();
        gFree.pop_back();
    } else {
        if (gSlots.size() >= kMaxWorlds) return fail(UNISON_ERROR_CAPACITY, "too many worlds");
        slot = std::uint32_t(gSlots.size());
        gSlots.emplace_back();
    }
    WorldSlot& s = gSlots[slot];
    s.generation = s.generation + 1 == 0 ? 1 : s.generation + 1;
    s.w2 = std::move(w2);
    s.w3 = std::move(w3);
    *out = {slot + 1, s.generation};
    return UNISON_OK;
}

template <class Def>
unisonError checkWorldDef(const Def* def, unisonWorldId* outWorld) {
    if (!def || !outWorld) return fail(UNISON_ERROR_NULL_POINTER, "def or outWorld is NULL");
    return UNISON_OK;
}

// Creates a world through its C++ constructor, mapping its Error to the C codes.
template <class World, class PublicDef>
unisonError createWorld(const PublicDef& def, unisonWorldId* outWorld) {
    std::unique_ptr<World> world;
    try {
        world = std::make_unique<World>(def);
    } catch (const Error& e) {
        const bool fp = std::string(e.what()).find("floating-point") != std::string::npos;
        return fail(fp ? UNISON_ERROR_FLOATING_POINT : UNISON_ERROR_INVALID_ARGUMENT, e.what());
    }
    if constexpr (std::is_same_v<World, World2D>) {
        return addWorld(std::move(world), nullptr, outWorld);
    } else {
        return addWorld(nullptr, std::move(world), outWorld);
    }
}

}  // namespace

WorldRef lookup(unisonWorldId id) {
    const std::lock_guard<std::mutex> lock(gMutex);
    const WorldSlot* s = slotOf(id);
    return s ? WorldRef{s->w2.get(), s->w3.get()} : WorldRef{};
}

unisonError fail(unisonError code, const std::string& message) {
    tLastError = message;
    return code;
}

unisonError copyBytes(const std::vector<std::uint8_t>& bytes, std::uint8_t* buffer, std::size_t capacity,
                      std::size_t* outSize) {
    if (!outSize) return fail(UNISON_ERROR_NULL_POINTER, "outSize is NULL");
    if (capacity > 0 && !buffer) return fail(UNISON_ERROR_NULL_POINTER, "buffer is NULL with a capacity > 0");
    *outSize = bytes.size();
    if (!buffer) return UNISON_OK;
    if (capacity < bytes.size())
        return fail(UNISON_ERROR_BUFFER_TOO_SMALL, "buffer holds " + std::to_string(capacity) + " bytes, " +
                                                       std::to_string(bytes.size()) + " needed");
    if (!bytes.empty()) std::memcpy(buffer, bytes.data(), bytes.size());
    return UNISON_OK;
}

bool fromC(unisonBodyType in, BodyType* out) {
    switch (in) {
        case UNISON_BODY_STATIC: *out = BodyType::staticBody; return true;
        case UNISON_BODY_KINEMATIC: *out = BodyType::kinematicBody; return true;
        case UNISON_BODY_DYNAMIC: *out = BodyType::dynamicBody; return true;
        case UNISON_BODY_MAX_ENUM: break;
    }
    return false;
}

unisonError fromC(const unisonShapeDef2& in, ShapeDef2D* out) {
    ShapeDef2D s;
    switch (in.type) {
        case UNISON_SHAPE2_CIRCLE: s = ShapeDef2D::circle(fromC(in.center), in.radius); break;
        case UNISON_SHAPE2_BOX:
            s = ShapeDef2D::box(in.halfExtents.x, in.halfExtents.y, fromC(in.center), in.angle);
            break;
        case UNISON_SHAPE2_POLYGON:
            if (in.pointCount < 0) return fail(UNISON_ERROR_INVALID_ARGUMENT, "polygon: pointCount must be >= 0");
            if (in.pointCount > 0 && !in.points) return fail(UNISON_ERROR_NULL_POINTER, "polygon: points is NULL");
            s.kind = ShapeKind2D::polygon;
            for (int i = 0; i < in.pointCount; ++i) s.points.push_back(fromC(in.points[i]));
            break;
        case UNISON_SHAPE2_SEGMENT: s = ShapeDef2D::segment(fromC(in.segmentStart), fromC(in.segmentEnd)); break;
        default: return fail(UNISON_ERROR_INVALID_ARGUMENT, "shape: unknown type");
    }
    s.density = in.density;
    s.friction = in.friction;
    s.restitution = in.restitution;
    *out = std::move(s);
    return UNISON_OK;
}

unisonError fromC(const unisonShapeDef3& in, ShapeDef3D* out) {
    ShapeDef3D s;
    if (in.type == UNISON_SHAPE3_HULL || in.type == UNISON_SHAPE3_MESH) {
        if (in.pointCount < 0 || in.triangleCount < 0)
            return fail(UNISON_ERROR_INVALID_ARGUMENT, "shape: counts must be >= 0");
        if (in.pointCount > 0 && !in.points) return fail(UNISON_ERROR_NULL_POINTER, "shape: points is NULL");
        for (int i = 0; i < in.pointCount; ++i) s.points.push_back(fromC(in.points[i]));
    }
    switch (in.type) {
        case UNISON_SHAPE3_SPHERE: s.kind = ShapeKind3D::sphere; break;
        case UNISON_SHAPE3_BOX: s.kind = ShapeKind3D::box; break;
        case UNISON_SHAPE3_HULL: s.kind = ShapeKind3D::hull; break;
        case UNISON_SHAPE3_PLANE: s.kind = ShapeKind3D::plane; break;
        case UNISON_SHAPE3_MESH:
            s.kind = ShapeKind3D::mesh;
            if (in.triangleCount > 0 && !in.triangles) return fail(UNISON_ERROR_NULL_POINTER, "mesh: triangles is NULL");
            for (int t = 0; t < in.triangleCount; ++t)
                s.triangles.push_back({in.triangles[3 * t], in.triangles[3 * t + 1], in.triangles[3 * t + 2]});
            break;
        default: return fail(UNISON_ERROR_INVALID_ARGUMENT, "shape: unknown type");
    }
    s.center = fromC(in.center);
    s.radius = in.radius;
    s.halfExtents = fromC(in.halfExtents);
    s.normal = fromC(in.normal);
    s.offset = in.offset;
    s.density = in.density;
    s.friction = in.friction;
    s.restitution = in.restitution;
    *out = std::move(s);
    return UNISON_OK;
}

// Steps a world unless its state is no longer finite (then nothing changes and the fault is the message).
template <class W>
unisonError stepWorld(W& w, const std::uint64_t* budget) {
    std::string why = w.fault();
    if (why.empty()) {
        if (budget) {
            w.step(*budget);
        } else {
            w.step();
        }
        why = w.fault();
        if (why.empty()) return UNISON_OK;
    }
    return fail(UNISON_ERROR_WORLD_FAULT, why);
}

}  // namespace unison::capi

using namespace unison;
using namespace unison::capi;

extern "C" {

const char* unisonErrorName(unisonError error) {
    switch (error) {
        case UNISON_OK: return "ok";
        case UNISON_ERROR_NULL_POINTER: return "null_pointer";
        case UNISON_ERROR_INVALID_ARGUMENT: return "invalid_argument";
        case UNISON_ERROR_INVALID_WORLD: return "invalid_world";
        case UNISON_ERROR_INVALID_BODY: return "invalid_body";
        case UNISON_ERROR_WRONG_DIMENSION: return "wrong_dimension";
        case UNISON_ERROR_BUFFER_TOO_SMALL: return "buffer_too_small";
        case UNISON_ERROR_BAD_DATA: return "bad_data";
        case UNISON_ERROR_CAPACITY: return "capacity";
        case UNISON_ERROR_FLOATING_POINT: return "floating_point";
        case UNISON_ERROR_INTERNAL: return "internal";
        case UNISON_ERROR_WORLD_FAULT: return "world_fault";
        case UNISON_ERROR_MAX_ENUM: break;
    }
    return "unknown";
}

const char* unisonLastErrorMessage(void) { return tLastError.c_str(); }

unisonVersion unisonGetVersion(void) { return {UNISON_VERSION_MAJOR, UNISON_VERSION_MINOR, UNISON_VERSION_PATCH}; }

uint64_t unisonWorkUnitsFromMilliseconds(double ms) { return workUnitsFromMilliseconds(ms); }

unisonWorldDef2 unisonDefaultWorldDef2(void) {
    const WorldDef2D d;
    return {toC(d.gravity), d.hz, d.enableSleep ? 1 : 0, d.stepBudget, toC(d.tasks)};
}

unisonWorldDef3 unisonDefaultWorldDef3(void) {
    const WorldDef3D d;
    return {toC(d.gravity), d.hz, d.enableSleep ? 1 : 0, d.stepBudget, toC(d.tasks)};
}

unisonBodyDef2 unisonDefaultBodyDef2(void) {
    const BodyDef2D d;
    return {UNISON_BODY_DYNAMIC, toC(d.position), d.angle, toC(d.linearVelocity), d.angularVelocity};
}

unisonBodyDef3 unisonDefaultBodyDef3(void) {
    const BodyDef3D d;
    return {UNISON_BODY_DYNAMIC, toC(d.position), toC(d.orientation), toC(d.linearVelocity), toC(d.angularVelocity)};
}

namespace {

unisonShapeDef2 shape2(const ShapeDef2D& s, unisonShapeType2 type) {
    unisonShapeDef2 out{};
    out.type = type;
    out.center = toC(s.center);
    out.radius = s.radius;
    out.halfExtents = toC(s.halfExtents);
    out.angle = s.angle;
    out.density = s.density;
    out.friction = s.friction;
    out.restitution = s.restitution;
    return out;
}

unisonShapeDef3 shape3(const ShapeDef3D& s, unisonShapeType3 type) {
    unisonShapeDef3 out{};
    out.type = type;
    out.center = toC(s.center);
    out.radius = s.radius;
    out.halfExtents = toC(s.halfExtents);
    out.normal = toC(s.normal);
    out.offset = s.offset;
    out.density = s.density;
    out.friction = s.friction;
    out.restitution = s.restitution;
    return out;
}

}  // namespace

unisonShapeDef2 unisonMakeCircle2(unisonVec2 center, double radius) {
    return shape2(ShapeDef2D::circle(fromC(center), radius), UNISON_SHAPE2_CIRCLE);
}

unisonShapeDef2 unisonMakeBox2(double hx, double hy) { return shape2(ShapeDef2D::box(hx, hy), UNISON_SHAPE2_BOX); }

unisonShapeDef2 unisonMakePolygon2(const unisonVec2* points, int count) {
    unisonShapeDef2 s = shape2(ShapeDef2D{}, UNISON_SHAPE2_POLYGON);
    s.points = points;
    s.pointCount = count;
    return s;
}

unisonShapeDef2 unisonMakeSegment2(unisonVec2 a, unisonVec2 b) {
    unisonShapeDef2 s = shape2(ShapeDef2D{}, UNISON_SHAPE2_SEGMENT);
    s.segmentStart = a;
    s.segmentEnd = b;
    return s;
}

unisonShapeDef3 unisonMakeSphere3(unisonVec3 center, double radius) {
    return shape3(ShapeDef3D::sphere(fromC(center), radius), UNISON_SHAPE3_SPHERE);
}

unisonShapeDef3 unisonMakeBox3(unisonVec3 halfExtents) {
    return shape3(ShapeDef3D::box(fromC(halfExtents)), UNISON_SHAPE3_BOX);
}

unisonShapeDef3 unisonMakeHull3(const unisonVec3* points, int count) {
    unisonShapeDef3 s = shape3(ShapeDef3D{}, UNISON_SHAPE3_HULL);
    s.points = points;
    s.pointCount = count;
    return s;
}

unisonShapeDef3 unisonMakePlane3(unisonVec3 normal, double offset) {
    return shape3(ShapeDef3D::plane(fromC(normal), offset), UNISON_SHAPE3_PLANE);
}

unisonShapeDef3 unisonMakeMesh3(const unisonVec3* vertices, int vertexCount, const int* triangles, int triangleCount) {
    unisonShapeDef3 s = shape3(ShapeDef3D{}, UNISON_SHAPE3_MESH);
    s.points = vertices;
    s.pointCount = vertexCount;
    s.triangles = triangles;
    s.triangleCount = triangleCount;
    return s;
}

unisonError unisonCreateWorld2(const unisonWorldDef2* def, unisonWorldId* outWorld) {
    return guard([&] {
        if (const unisonError e = checkWorldDef(def, outWorld)) return e;
        WorldDef2D d;
        d.gravity = fromC(def->gravity);
        d.hz = def->hz;
        d.enableSleep = def->enableSleep != 0;
        d.stepBudget = def->stepBudget;
        d.tasks = fromC(def->tasks);
        return createWorld<World2D>(d, outWorld);
    });
}

unisonError unisonCreateWorld3(const unisonWorldDef3* def, unisonWorldId* outWorld) {
    return guard([&] {
        if (const unisonError e = checkWorldDef(def, outWorld)) return e;
        WorldDef3D d;
        d.gravity = fromC(def->gravity);
        d.hz = def->hz;
        d.enableSleep = def->enableSleep != 0;
        d.stepBudget = def->stepBudget;
        d.tasks = fromC(def->tasks);
        return createWorld<World3D>(d, outWorld);
    });
}

unisonError unisonDestroyWorld(unisonWorldId world) {
    return guard([&] {
        std::unique_ptr<World2D> w2;
        std::unique_ptr<World3D> w3;
        {
            const std::lock_guard<std::mutex> lock(gMutex);
            WorldSlot* s = slotOf(world);
            if (!s) return fail(UNISON_ERROR_INVALID_WORLD, "invalid world id");
            w2 = std::move(s->w2);
            w3 = std::move(s->w3);
            gFree.push_back(world.index1 - 1);
        }
        return UNISON_OK;  // the world is freed here, outside the lock
    });
}

int unisonWorldIsValid(unisonWorldId world) {
    const WorldRef ref = lookup(world);
    return ref.w2 || ref.w3 ? 1 : 0;
}

unisonError unisonGetWorldDimension(unisonWorldId world, int* outDimension) {
    return guard([&] {
        const WorldRef ref = lookup(world);
        if (!ref.w2 && !ref.w3) return fail(UNISON_ERROR_INVALID_WORLD, "invalid world id");
        if (!outDimension) return fail(UNISON_ERROR_NULL_POINTER, "outDimension is NULL");
        *outDimension = ref.w2 ? 2 : 3;
        return UNISON_OK;
    });
}

unisonError unisonStep(unisonWorldId world) {
    return withWorld(world, [&](auto& w) { return stepWorld(w, nullptr); });
}

unisonError unisonStepWithBudget(unisonWorldId world, uint64_t budget) {
    return withWorld(world, [&](auto& w) { return stepWorld(w, &budget); });
}

unisonError unisonSetStepBudget(unisonWorldId world, uint64_t budget) {
    return withWorld(world, [&](auto& w) {
        w.setStepBudget(budget);
        return UNISON_OK;
    });
}

unisonError unisonGetStepBudget(unisonWorldId world, uint64_t* outBudget) {
    return withWorld(world, [&](auto& w) {
        if (!outBudget) return fail(UNISON_ERROR_NULL_POINTER, "outBudget is NULL");
        *outBudget = w.stepBudget();
        return UNISON_OK;
    });
}

unisonError unisonSetTaskSystem(unisonWorldId world, const unisonTaskSystem* tasks) {
    return withWorld(world, [&](auto& w) {
        if (!tasks) return fail(UNISON_ERROR_NULL_POINTER, "tasks is NULL");
        return w.setTaskSystem(fromC(*tasks))
                   ? UNISON_OK
                   : fail(UNISON_ERROR_INVALID_ARGUMENT, "workerCount must be >= 1, with both callbacks or neither");
    });
}

unisonError unisonGetWorldFault(unisonWorldId world, char* buffer, size_t capacity, size_t* outSize) {
    return withWorld(world, [&](auto& w) {
        const std::string why = w.fault();
        std::vector<std::uint8_t> bytes(why.begin(), why.end());
        bytes.push_back(0);
        return copyBytes(bytes, reinterpret_cast<std::uint8_t*>(buffer), capacity, outSize);
    });
}

unisonError unisonGetStepCount(unisonWorldId world, uint64_t* outSteps) {
    return withWorld(world, [&](auto& w) {
        if (!outSteps) return fail(UNISON_ERROR_NULL_POINTER, "outSteps is NULL");
        *outSteps = w.stepCount();
        return UNISON_OK;
    });
}

unisonError unisonGetStepInfo(unisonWorldId world, unisonStepInfo* outInfo) {
    return withWorld(world, [&](auto& w) {
        if (!outInfo) return fail(UNISON_ERROR_NULL_POINTER, "outInfo is NULL");
        const StepInfo s = w.stepInfo();
        *outInfo = {s.islands,        s.awakeIslands,       s.contacts,          s.pivots,
                    s.work,           s.budget,             s.minimumWork,       s.overrun,
                    s.exactIslands,   s.approximateIslands, s.failedIslands,     s.unsolvedIslands,
                    s.maxResidual,    s.maxApproximateResidual, s.maxPenetration, s.activeSetIslands};
        return UNISON_OK;
    });
}

unisonError unisonSetGravity2(unisonWorldId world, unisonVec2 gravity) {
    return guard([&] {
        unisonError code;
        World2D* w = worldOf<2>(world, &code);
        if (code) return code;
        return w->setGravity(fromC(gravity)) ? UNISON_OK : fail(UNISON_ERROR_INVALID_ARGUMENT, "gravity must be finite");
    });
}

unisonError unisonSetGravity3(unisonWorldId world, unisonVec3 gravity) {
    return guard([&] {
        unisonError code;
        World3D* w = worldOf<3>(world, &code);
        if (code) return code;
        return w->setGravity(fromC(gravity)) ? UNISON_OK : fail(UNISON_ERROR_INVALID_ARGUMENT, "gravity must be finite");
    });
}

unisonError unisonGetStateHash(unisonWorldId world, uint64_t* outHash) {
    return withWorld(world, [&](auto& w) {
        if (!outHash) return fail(UNISON_ERROR_NULL_POINTER, "outHash is NULL");
        *outHash = w.stateHash();
        return UNISON_OK;
    });
}

unisonError unisonSaveSnapshot(unisonWorldId world, uint8_t* buffer, size_t capacity, size_t* outSize) {
    return withWorld(world, [&](auto& w) { return copyBytes(w.snapshot(), buffer, capacity, outSize); });
}

unisonError unisonRestoreSnapshot(unisonWorldId world, const uint8_t* data, size_t size) {
    return withWorld(world, [&](auto& w) {
        if (!data) return fail(UNISON_ERROR_NULL_POINTER, "data is NULL");
        std::string error;
        return w.restore(data, size, &error) ? UNISON_OK : fail(UNISON_ERROR_BAD_DATA, error);
    });
}

unisonError unisonSaveCompactState(unisonWorldId world, uint8_t* buffer, size_t capacity, size_t* outSize) {
    return withWorld(world, [&](auto& w) {
        std::vector<std::uint8_t> bytes;
        w.saveCompact(bytes);
        return copyBytes(bytes, buffer, capacity, outSize);
    });
}

unisonError unisonRestoreCompactState(unisonWorldId world, const uint8_t* data, size_t size) {
    return withWorld(world, [&](auto& w) {
        if (!data) return fail(UNISON_ERROR_NULL_POINTER, "data is NULL");
        std::string error;
        return w.restoreCompact(data, size, &error) ? UNISON_OK : fail(UNISON_ERROR_BAD_DATA, error);
    });
}

void unisonFreeBuffer(unisonBuffer* buffer) {
    if (!buffer) return;
    std::free(buffer->data);
    buffer->data = nullptr;
    buffer->size = 0;
}

unisonError unisonRecord(const char* sceneJson, const char* inputsJson, int steps, int snapshotEvery,
                         unisonBuffer* outRecording) {
    return guard([&] {
        if (!sceneJson || !outRecording) return fail(UNISON_ERROR_NULL_POINTER, "sceneJson or outRecording is NULL");
        std::string error;
        const std::vector<std::uint8_t> bytes = recordMatch(sceneJson, inputsJson ? inputsJson : "", steps, snapshotEvery, &error);
        if (bytes.empty()) return fail(UNISON_ERROR_INVALID_ARGUMENT, error);
        auto* data = static_cast<std::uint8_t*>(std::malloc(bytes.size()));
        if (!data) return fail(UNISON_ERROR_INTERNAL, "out of memory");
        std::memcpy(data, bytes.data(), bytes.size());
        *outRecording = {data, bytes.size()};
        return UNISON_OK;
    });
}

unisonError unisonVerifyRecording(const uint8_t* data, size_t size, unisonVerifyResult* outResult) {
    return guard([&] {
        if (!data || !outResult) return fail(UNISON_ERROR_NULL_POINTER, "data or outResult is NULL");
        VerifyResult r;
        std::string error;
        if (!verifyRecording(data, size, &r, &error)) return fail(UNISON_ERROR_BAD_DATA, error);
        unisonVerifyResult out{};
        out.match = r.match ? 1 : 0;
        out.ticks = r.ticks;
        out.firstDesyncTick = r.firstDesyncTick;
        out.recordedHash = r.recordedHash;
        out.replayedHash = r.replayedHash;
        out.differingFields = r.differingFields;
        std::strncpy(out.summary, r.summary.c_str(), sizeof out.summary - 1);
        *outResult = out;
        return UNISON_OK;
    });
}

}  // extern "C"
