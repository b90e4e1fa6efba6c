// Writes the .vdb test files that pyopenvdb cannot: other compression
// settings than its Blosc default.
// With Debian's OpenVDB 10.0.1 (`apt-get install libopenvdb-dev`), after
// make_test_vdbs.py, from this directory:
//
//     (libboost-dev is needed too)
//     g++ -std=c++17 -O1 make_cpp_vdbs.cpp -o /tmp/make_cpp_vdbs \
//         -lopenvdb -ltbb -lImath-3_1
//     /tmp/make_cpp_vdbs
//
// Files:
// - sphere_zip.vdb: sphere.vdb's grid written with zip and active-mask
//   compression (io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK), its class
//   "unknown" instead of "fog volume".
// - tiles_raw.vdb: tiles.vdb's grid with active-mask compression only (no
//   zip, no Blosc).
//
// No TranslationMap or UnitaryMap file: OpenVDB's Transform simplifies
// every linear map it is given (a TranslationMap becomes a
// UniformScaleTranslateMap, a UnitaryMap an AffineMap), so OpenVDB 10
// does not write them.
#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>

using namespace openvdb;

static GridPtrVecPtr read_all(const char* name) {
    io::File f(name);
    f.open();
    GridPtrVecPtr grids = f.getGrids();
    f.close();
    return grids;
}

static void write(const char* name, const GridPtrVec& grids, uint32_t compression) {
    io::File f(name);
    f.setCompression(compression);
    f.write(grids);
    f.close();
}

int main() {
    initialize();
    // OpenVDB does not zip fog volumes or level sets (Archive.cc
    // setGridCompression), so the copy's class is made "unknown".
    GridPtrVecPtr sphere = read_all("sphere.vdb");
    for (auto& g : *sphere) g->setGridClass(GRID_UNKNOWN);
    write("sphere_zip.vdb", *sphere, io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK);
    write("tiles_raw.vdb", *read_all("tiles.vdb"), io::COMPRESS_ACTIVE_MASK);

    return 0;
}
