// The only file in vpm that includes OpenVDB headers.
#include "io/vdb_io.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <unistd.h>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include "core/error.h"

namespace vpm {

namespace fs = std::filesystem;

namespace {

void ensure_openvdb_initialized() {
    static std::once_flag flag;
    std::call_once(flag, [] { openvdb::initialize(); });
}

std::string grids_found(const std::vector<VdbGridInfo>& grids) {
    if (grids.empty()) return "the file holds no grids";
    std::string s = "grids found:";
    for (size_t i = 0; i < grids.size(); ++i)
        s += (i ? ", '" : " '") + grids[i].name + "' (" + grids[i].type + ")";
    return s;
}

std::string coord_str(const openvdb::Coord& c) {
    return "(" + std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " + std::to_string(c.z()) + ")";
}

std::string num_str(double v) {
    std::ostringstream s;
    s.precision(9);
    s << v;
    return s.str();
}

// Structural check of the file before OpenVDB parses it. OpenVDB does not check its stream state
// while reading, so a truncated file makes it read garbage sizes (multi-GB allocations, minutes of
// work) or, worse, garbage voxel values without any error. We walk the header, the file metadata
// and the grid descriptors (format of io/Archive.cc, io/GridDescriptor.cc, MetaMap::readMeta) and
// require every length and every grid's byte range to lie inside the file. Files older than
// format 222 (before OpenVDB 3) are passed on unchecked.
void check_structure(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path + ": cannot open file");
    in.seekg(0, std::ios::end);
    const int64_t size = static_cast<int64_t>(in.tellg());
    in.seekg(0);
    int64_t pos = 0;
    auto fail = [&](const std::string& what) -> void {
        throw FileError(path + ": corrupt or truncated OpenVDB file (" + what + " at byte " + std::to_string(pos) +
                        " of " + std::to_string(size) + ")");
    };
    auto read_bytes = [&](void* dst, int64_t n, const char* what) {
        if (n < 0 || pos + n > size) fail(std::string("unexpected end of file reading ") + what);
        in.read(static_cast<char*>(dst), n);
        if (!in) fail(std::string("read error in ") + what);
        pos += n;
    };
    auto skip = [&](int64_t n, const char* what) {
        if (n < 0 || pos + n > size) fail(std::string("unexpected end of file in ") + what);
        pos += n;
        in.seekg(pos);
    };
    auto skip_string = [&](const char* what) {
        uint32_t len = 0;
        read_bytes(&len, 4, what);
        skip(len, what);
    };
    int64_t magic = 0;
    if (size < 8) throw FileError(path + ": not a readable OpenVDB file (only " + std::to_string(size) + " bytes)");
    read_bytes(&magic, 8, "magic number");
    if (magic != 0x56444220) throw FileError(path + ": not a readable OpenVDB file (no VDB magic number)");
    uint32_t version = 0, lib[2];
    read_bytes(&version, 4, "file version");
    if (version < 222) return;
    read_bytes(lib, 8, "library version");
    char has_offsets = 0;
    read_bytes(&has_offsets, 1, "header");
    skip(36, "uuid");
    int32_t meta_count = 0;
    read_bytes(&meta_count, 4, "file metadata count");
    if (meta_count < 0 || meta_count > 1000000) fail("bad file metadata count");
    for (int32_t i = 0; i < meta_count; ++i) {
        skip_string("metadata name");
        skip_string("metadata type");
        skip_string("metadata value");
    }
    int32_t grid_count = 0;
    read_bytes(&grid_count, 4, "grid count");
    if (grid_count < 0 || grid_count > 1000000) fail("bad grid count");
    if (!has_offsets) return;   // a stream without grid offsets: nothing more to check cheaply
    for (int32_t i = 0; i < grid_count; ++i) {
        skip_string("grid name");
        skip_string("grid type");
        skip_string("instance parent name");
        int64_t offsets[3];
        read_bytes(offsets, 24, "grid offsets");
        if (!(offsets[0] >= pos && offsets[0] <= offsets[1] && offsets[1] <= offsets[2]))
            fail("bad offsets of grid " + std::to_string(i));
        if (offsets[2] > size)
            fail("grid " + std::to_string(i) + " should extend to byte " + std::to_string(offsets[2]));
        pos = offsets[2];
        in.seekg(pos);
    }
}

// Opens `path` fully (no delayed loading: a truncated file fails here or in readGrid, not later
// inside a render).
void open_file(openvdb::io::File& file, const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw FileError(path + ": file not found");
    if (fs::is_directory(path, ec)) throw FileError(path + ": is a directory, expected an OpenVDB file");
    check_structure(path);
    try {
        file.open(/*delayLoad=*/false);
    } catch (const std::exception& e) {
        throw FileError(path + ": not a readable OpenVDB file (" + e.what() + ")");
    }
}

std::vector<VdbGridInfo> read_grid_infos(openvdb::io::File& file, const std::string& path) {
    std::vector<VdbGridInfo> out;
    try {
        openvdb::GridPtrVecPtr metas = file.readAllGridMetadata();
        for (const auto& g : *metas) out.push_back({g->getName(), g->valueType()});
    } catch (const std::exception& e) {
        throw FileError(path + ": corrupt or truncated OpenVDB file (" + e.what() + ")");
    }
    return out;
}

Eigen::Affine3d to_eigen(const openvdb::math::Mat4d& m) {
    // OpenVDB multiplies row vectors: world = index * M, translation in row 3.
    Eigen::Affine3d a = Eigen::Affine3d::Identity();
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) a.linear()(j, i) = m(i, j);
        a.translation()(i) = m(3, i);
    }
    return a;
}

openvdb::math::Mat4d to_openvdb(const Eigen::Affine3d& a) {
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) m(i, j) = a.linear()(j, i);
        m(3, i) = a.translation()(i);
    }
    return m;
}

void write_grids(const std::string& path, const openvdb::GridPtrVec& grids) {
    const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    try {
        openvdb::io::File out(tmp);
        out.write(grids);
        out.close();
    } catch (const std::exception& e) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw FileError(path + ": cannot write OpenVDB file (" + e.what() + ")");
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw FileError(path + ": cannot rename temporary file into place (" + ec.message() + ")");
    }
}

}  // namespace

std::vector<VdbGridInfo> list_vdb_grids(const std::string& path) {
    ensure_openvdb_initialized();
    openvdb::io::File file(path);
    open_file(file, path);
    auto infos = read_grid_infos(file, path);
    file.close();
    return infos;
}

namespace {

bool is_scalar_type(const std::string& type) { return type == "float" || type == "double"; }

// Converts a float or double grid (values to float) into a finalized DensityGrid.
template <class GridT>
DensityGrid convert_grid(const GridT& grid, const std::string& where) {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename GridT::ValueType;
    const TreeT& tree = grid.tree();
    if (grid.background() != ValueT(0))
        throw FileError(where + "background value " + num_str(double(grid.background())) +
                        " is not 0 (a density grid must be 0 outside its active region)");
    if (tree.activeVoxelCount() == 0) throw FileError(where + "grid is empty (no active voxels)");

    // Density values must be finite and >= 0: negative extinction has no physical meaning and
    // would break delta / ratio tracking (the majorant must bound sigma_t from above and ratio
    // tracking weights 1 - sigma/majorant would exceed 1). We reject rather than clamp silently.
    // Every stored value is checked, inactive ones included, because trilinear lookup reads them
    // too; values are checked after conversion to float (a double beyond 3.4e38 is rejected).
    auto check_value = [&](ValueT v, const openvdb::Coord& c, const char* what) {
        const float f = static_cast<float>(v);
        if (!std::isfinite(f))
            throw FileError(where + what + " " + coord_str(c) + " has non-finite value " + num_str(double(v)) +
                            "; densities must be finite");
        if (f < 0.0f)
            throw FileError(where + what + " " + coord_str(c) + " has negative value " + num_str(double(v)) +
                            "; densities must be >= 0");
    };

    // Bounding box of all stored data: leaves plus tiles (active tiles, and inactive tiles whose
    // value is not the background 0).
    openvdb::CoordBBox box;
    struct Tile {
        openvdb::CoordBBox box;
        float value;
    };
    std::vector<Tile> tiles;
    constexpr openvdb::Index kLeafSize = TreeT::LeafNodeType::SIZE;
    static_assert(kLeafSize == DensityGrid::kVoxels, "OpenVDB leaves must be 8^3");
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        const auto& leaf = *it;
        for (openvdb::Index i = 0; i < kLeafSize; ++i) check_value(leaf.getValue(i), leaf.offsetToGlobalCoord(i), "voxel");
        box.expand(leaf.getNodeBoundingBox());
    }
    {
        auto it = tree.cbeginValueAll();
        it.setMaxDepth(TreeT::ValueAllCIter::LEAF_DEPTH - 1);   // tiles only
        for (; it; ++it) {
            const ValueT v = *it;
            if (!it.isValueOn() && v == ValueT(0)) continue;
            openvdb::CoordBBox tb;
            it.getBoundingBox(tb);
            check_value(v, tb.min(), "tile at");
            tiles.push_back({tb, static_cast<float>(v)});
            box.expand(tb);
        }
    }

    DensityGrid out;
    try {
        out = DensityGrid(Vec3i(box.min().x(), box.min().y(), box.min().z()),
                          Vec3i(box.max().x(), box.max().y(), box.max().z()));
    } catch (const std::exception& e) {
        throw FileError(where + "index bounding box " + coord_str(box.min()) + " - " + coord_str(box.max()) +
                        " is too large: " + e.what());
    }
    for (const Tile& t : tiles) {
        // Tiles above leaf level are aligned to (multiples of) 8^3 blocks.
        for (int bx = t.box.min().x() >> 3; bx <= t.box.max().x() >> 3; ++bx)
            for (int by = t.box.min().y() >> 3; by <= t.box.max().y() >> 3; ++by)
                for (int bz = t.box.min().z() >> 3; bz <= t.box.max().z() >> 3; ++bz)
                    out.set_block_constant(Vec3i(bx, by, bz), t.value);
    }
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        const auto& leaf = *it;
        const openvdb::Coord o = leaf.origin();
        float* dst = out.dense_block(Vec3i(o.x() >> 3, o.y() >> 3, o.z() >> 3));
        for (openvdb::Index i = 0; i < kLeafSize; ++i) dst[i] = static_cast<float>(leaf.getValue(i));
    }
    out.set_active_voxel_count(static_cast<int64_t>(tree.activeVoxelCount()));
    return out;
}

}  // namespace

DensityGrid load_vdb_density(const std::string& path, const std::string& grid_name) {
    ensure_openvdb_initialized();
    openvdb::io::File file(path);
    open_file(file, path);
    const std::vector<VdbGridInfo> infos = read_grid_infos(file, path);

    // Select the grid: float or double (converted to float).
    std::string name = grid_name;
    if (name.empty()) {
        for (const auto& g : infos)
            if (is_scalar_type(g.type)) { name = g.name; break; }
        if (name.empty())
            throw ConfigError(path + ": no float or double grid to use as density; " + grids_found(infos));
    } else {
        const VdbGridInfo* found = nullptr;
        for (const auto& g : infos)
            if (g.name == name) { found = &g; break; }
        if (!found) throw ConfigError(path + ": no grid named '" + name + "'; " + grids_found(infos));
        if (!is_scalar_type(found->type))
            throw ConfigError(path + ": grid '" + name + "' holds " + found->type +
                              " values, a density needs a float (or double) grid; " + grids_found(infos));
    }

    openvdb::GridBase::Ptr base;
    try {
        base = file.readGrid(name);
        file.close();
    } catch (const std::exception& e) {
        throw FileError(path + ": cannot read grid '" + name + "', the file is corrupt or truncated (" + e.what() +
                        ")");
    }
    const std::string where = path + ": grid '" + name + "': ";
    if (!base) throw FileError(where + "could not be read");

    if (!base->transform().isLinear())
        throw FileError(where + "transform '" + base->transform().mapType() +
                        "' is not affine (frustum transforms are not supported)");
    const Eigen::Affine3d index_to_world = to_eigen(base->transform().baseMap()->getAffineMap()->getMat4());
    if (!index_to_world.matrix().allFinite() || std::abs(index_to_world.linear().determinant()) < 1e-300)
        throw FileError(where + "index-to-world transform is singular or not finite");

    DensityGrid out;
    if (auto fg = openvdb::gridConstPtrCast<openvdb::FloatGrid>(base)) {
        out = convert_grid(*fg, where);
    } else if (auto dg = openvdb::gridConstPtrCast<openvdb::DoubleGrid>(base)) {
        out = convert_grid(*dg, where);
    } else {
        throw FileError(where + "is a " + base->valueType() + " grid, expected float or double");
    }
    out.set_name(name);
    out.set_index_to_world(index_to_world);
    out.finalize();
    return out;
}

void write_vdb_density(const std::string& path, const std::string& name, const DensityGrid& grid) {
    ensure_openvdb_initialized();
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setName(name);
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    g->setTransform(openvdb::math::Transform::createLinearTransform(to_openvdb(grid.index_to_world())));
    if (!grid.empty()) {
        auto acc = g->getAccessor();
        const Vec3i lo = grid.voxel_lo(), hi = grid.voxel_hi();
        for (int x = lo.x(); x <= hi.x(); ++x)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int z = lo.z(); z <= hi.z(); ++z) {
                    const float v = grid.voxel(x, y, z);
                    if (v != 0.0f) acc.setValueOn(openvdb::Coord(x, y, z), v);
                }
    }
    g->pruneGrid(0.0f);
    write_grids(path, openvdb::GridPtrVec{g});
}

void write_vdb_test_grid(const std::string& path, const std::string& name, const std::string& kind) {
    ensure_openvdb_initialized();
    openvdb::GridBase::Ptr base;
    if (kind == "vec3s") {
        auto g = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
        g->tree().setValueOn(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1.0f, 2.0f, 3.0f));
        base = g;
    } else if (kind == "int32") {
        auto g = openvdb::Int32Grid::create(0);
        g->tree().setValueOn(openvdb::Coord(1, 2, 3), 7);
        base = g;
    } else if (kind == "empty_float") {
        base = openvdb::FloatGrid::create(0.0f);
    } else if (kind == "frustum_float") {
        auto g = openvdb::FloatGrid::create(0.0f);
        g->tree().setValueOn(openvdb::Coord(1, 2, 3), 1.0f);
        g->setTransform(openvdb::math::Transform::createFrustumTransform(
            openvdb::BBoxd(openvdb::Vec3d(0.0), openvdb::Vec3d(16.0)), 0.5, 2.0));
        base = g;
    } else {
        throw std::invalid_argument("write_vdb_test_grid: unknown kind '" + kind + "'");
    }
    base->setName(name);
    write_grids(path, openvdb::GridPtrVec{base});
}

}  // namespace vpm
