// api/capi_internal.h — what the C API's files (capi.cpp, capi_bodies.cpp) share: the registry of worlds behind
// unisonWorldId, the per-thread last error, the guard that turns exceptions into error codes, the array and buffer
// conventions of unison.h, and conversions between the C structs and the C++ API's value types.
//
// Invariants: a world id is valid while its slot holds a world of the same generation; slots are reused last in,
// first out with the generation incremented (never 0), as body ids are. The registry is guarded by one mutex;
// a world itself is not (unison.h: one world, one thread at a time).
#pragma once

#include <unison/unison.h>
#include <unison/world2d.h>
#include <unison/world3d.h>

#include <cstring>
#include <exception>
#include <string>
#include <vector>

namespace unison::capi {

/// The worlds of one id: exactly one of the two is set for a live world.
struct WorldRef {
    World2D* w2 = nullptr;
    World3D* w3 = nullptr;
};

/// The world an id names (both null for a null, stale or destroyed id).
WorldRef lookup(unisonWorldId id);

/// Records the calling thread's last error message and returns `code`.
unisonError fail(unisonError code, const std::string& message);

/// Runs body(), turning any exception into UNISON_ERROR_INTERNAL with its message.
template <class F>
unisonError guard(F&& body) {
    try {
        return body();
    } catch (const std::exception& e) {
        return fail(UNISON_ERROR_INTERNAL, std::string("internal error: ") + e.what());
    } catch (...) {
        return fail(UNISON_ERROR_INTERNAL, "internal error");
    }
}

/// The world of `id` if it is valid and of `dimension` (2 or 3); otherwise an error code in *code.
template <int Dim>
auto worldOf(unisonWorldId id, unisonError* code) {
    const WorldRef ref = lookup(id);
    *code = UNISON_OK;
    if (!ref.w2 && !ref.w3) {
        *code = fail(UNISON_ERROR_INVALID_WORLD, "invalid world id");
    } else if ((Dim == 2 && !ref.w2) || (Dim == 3 && !ref.w3)) {
        *code = fail(UNISON_ERROR_WRONG_DIMENSION, Dim == 2 ? "a 2D function on a 3D world" : "a 3D function on a 2D world");
    }
    if constexpr (Dim == 2) {
        return ref.w2;
    } else {
        return ref.w3;
    }
}

/// Applies f to the world of `id` whatever its dimension (f takes World2D& or World3D&).
template <class F>
unisonError withWorld(unisonWorldId id, F&& f) {
    return guard([&] {
        const WorldRef ref = lookup(id);
        if (ref.w2) return f(*ref.w2);
        if (ref.w3) return f(*ref.w3);
        return fail(UNISON_ERROR_INVALID_WORLD, "invalid world id");
    });
}

/// The array convention of unison.h: (NULL, 0) asks for the count; a smaller buffer gets nothing.
template <class C, class T, class Convert>
unisonError copyOut(const std::vector<T>& items, C* out, int capacity, int* outCount, Convert convert) {
    if (!outCount) return fail(UNISON_ERROR_NULL_POINTER, "outCount is NULL");
    if (capacity < 0) return fail(UNISON_ERROR_INVALID_ARGUMENT, "capacity must be >= 0");
    if (capacity > 0 && !out) return fail(UNISON_ERROR_NULL_POINTER, "out is NULL with a capacity > 0");
    *outCount = int(items.size());
    if (!out) return UNISON_OK;
    if (std::size_t(capacity) < items.size())
        return fail(UNISON_ERROR_BUFFER_TOO_SMALL, "buffer holds " + std::to_string(capacity) + " entries, " +
                                                       std::to_string(items.size()) + " needed");
    for (std::size_t i = 0; i < items.size(); ++i) out[i] = convert(items[i]);
    return UNISON_OK;
}

/// The same convention for bytes.
unisonError copyBytes(const std::vector<std::uint8_t>& bytes, std::uint8_t* buffer, std::size_t capacity,
                      std::size_t* outSize);

inline unisonBodyId toC(BodyId id) { return {id.index1, id.generation}; }
inline BodyId fromC(unisonBodyId id) { return {id.index1, id.generation}; }
inline unisonVec2 toC(Vec2D v) { return {v.x, v.y}; }
inline Vec2D fromC(unisonVec2 v) { return {v.x, v.y}; }
inline unisonVec3 toC(Vec3D v) { return {v.x, v.y, v.z}; }
inline Vec3D fromC(unisonVec3 v) { return {v.x, v.y, v.z}; }
inline unisonQuat toC(Quat3D q) { return {q.w, q.x, q.y, q.z}; }
inline Quat3D fromC(unisonQuat q) { return {q.w, q.x, q.y, q.z}; }
inline unisonShapeRef toC(const ShapeRef& r) { return {toC(r.body), r.shape}; }
inline unisonTouchEvent toC(const TouchEvent& e) { return {toC(e.a), toC(e.b)}; }
// The callback types of unison.h and unison/types.h are the same function types (C and C++ linkage name the same
// calling convention on every supported compiler).
inline unisonTaskSystem toC(const TaskSystem& t) {
    return {t.workerCount, reinterpret_cast<unisonEnqueueTaskCallback*>(t.enqueueTask),
            reinterpret_cast<unisonFinishTaskCallback*>(t.finishTask), t.userContext};
}
inline TaskSystem fromC(const unisonTaskSystem& t) {
    return {t.workerCount, reinterpret_cast<EnqueueTaskCallback*>(t.enqueueTask),
            reinterpret_cast<FinishTaskCallback*>(t.finishTask), t.userContext};
}

/// A C shape as the C++ API's; an error code (and a message) when its pointers or counts are invalid.
unisonError fromC(const unisonShapeDef2& in, ShapeDef2D* out);
unisonError fromC(const unisonShapeDef3& in, ShapeDef3D* out);

/// A body type from C; false for a value outside the enum.
bool fromC(unisonBodyType in, BodyType* out);

}  // namespace unison::capi
