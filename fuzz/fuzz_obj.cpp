// fuzz/fuzz_obj.cpp — OBJ text (scenes/obj_mesh.cpp): parse at a scale from the first byte, then build the mesh
// (makeMesh checks that it is closed, oriented and has volume) and, when it is accepted, a body from it.
#include "fuzz_support.h"
#include "obj_mesh.h"
#include "world3d.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace unison;
    if (size == 0) return 0;
    const double scale = 0.01 * double(1 + data[0]);
    try {
        const scenes::ObjMesh m = scenes::parseObj(fuzz::text(data + 1, size - 1), "fuzz", scale);
        std::vector<Shape3> shapes(1);
        if (!makeMesh(m.vertices, m.triangles, &shapes[0]).empty()) return 0;
        World3 world;
        if (world.createBody(BodyDef3{}, shapes).isNull()) return 0;
        fuzz::stepSnapshotRestore(world, 1);
    } catch (const jsonio::JsonError&) {
    }
    return 0;
}
