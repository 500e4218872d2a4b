// Plant import against hand-computed ground truth: files the test writes itself (COLLADA in
// two unit styles, OBJ + MTL), checked for size, up axis, classes, instances, ground-truth
// density, duplicates, budgets, round trips through the plant folder and placement in worlds.

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>

#include "canopy/common/error.h"
#include "canopy/world/plant_import.h"
#include "canopy/world/world.h"
#include "same_plants.h"
#include "plant_files.h"

namespace canopy::world {
namespace {

namespace fs = std::filesystem;
using namespace canopy::test_plant;

std::string temp_dir(const std::string& name) {
  const std::string d = testing::TempDir() + "/plant_import_" + name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string write_collada(const std::string& name, bool new_style, bool b_unripe = false) {
  const std::string path = temp_dir(name) + "/plant.dae";
  write_text(path, collada(new_style, b_unripe));
  return path;
}

ImportOptions capsicum() {
  ImportOptions o;
  o.rules = class_preset("capsicum");
  return o;
}

const ImportedPart* fruit_part(const ImportedPlant& p, int k) {
  for (const auto& part : p.parts)
    if (part.fruit == k) return &part;
  return nullptr;
}

// Expected centres in the plant frame: the base (stem bottom centre) at the origin, metres.
Vec3 expected_centre(const P& c_in) { return Vec3(c_in[0] - kBaseXIn, c_in[1] - kBaseYIn, c_in[2]) * kInch; }

TEST(PlantImport, ColladaZUpWithScaleInNodeStandsUprightAtItsBase) {
  const ImportedPlant p = import_plant(write_collada("new", true), capsicum());
  const ImportReport& r = p.report;
  EXPECT_EQ(r.up, "z");
  EXPECT_DOUBLE_EQ(r.file_unit_m, 1.0);
  EXPECT_DOUBLE_EQ(r.unit_scale, 1.0);
  // x: fruit B's left face (3.5 in) to the leaf tip (20 in); y: the cubes (3 in); z: the stem.
  EXPECT_NEAR(r.size_m.x(), 16.5 * kInch, 1e-6);
  EXPECT_NEAR(r.size_m.y(), 3.0 * kInch, 1e-6);
  EXPECT_NEAR(r.size_m.z(), kHeightIn * kInch, 1e-6);  // upright: assimp's Z-up -> Y-up is off
  EXPECT_NEAR(r.radius_m, std::hypot(10.0, 1.0) * kInch, 1e-6);  // leaf tip corner
  EXPECT_EQ(r.triangles_in, 15 + 3 * 12);  // leaf group (with the sliver), two cubes and the fragment
  EXPECT_EQ(r.degenerate_dropped, 1);
  EXPECT_EQ(r.duplicate_triangles, 0);
  EXPECT_EQ(r.fragments_merged, 1);
  EXPECT_EQ(r.fragments_dropped, 0);
  ASSERT_EQ(p.truth.fruits.size(), 2u);
  ASSERT_EQ(p.parts.size(), 3u);  // leaf material + two fruit instances
  EXPECT_EQ(p.parts[0].class_name, "leaf");
  EXPECT_EQ(p.parts[0].mesh.faces.size(), 14u);
  EXPECT_FLOAT_EQ(p.parts[0].rgba[1], 0.6f);  // the material's diffuse colour
  const ImportedPart* a = fruit_part(p, 0);
  const ImportedPart* b = fruit_part(p, 1);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->mesh.faces.size(), 24u);  // the cube and its merged fragment
  EXPECT_EQ(b->mesh.faces.size(), 12u);
  EXPECT_TRUE(a->target && b->target);
  // Fruit B's bounding box centre; fruit A's box reaches up to the fragment's top (+0.4 in).
  EXPECT_LT((p.truth.fruits[1].center - expected_centre(kFruitB)).norm(), 1e-6);
  EXPECT_LT((p.truth.fruits[0].center - expected_centre(kFruitA) - Vec3(0, 0, 0.2 * kInch)).norm(), 1e-6);
}

TEST(PlantImport, SurfaceGroundTruthHasTheProceduralDensityAndLiesOnTheFruit) {
  ImportOptions o = capsicum();
  o.point_spacing_m = 0.003;
  const ImportedPlant p = import_plant(write_collada("density", true), o);
  const FruitTruth& b = p.truth.fruits[1];
  const double side = kFruitSideIn * kInch;
  EXPECT_NEAR(b.surface_area_m2, 6 * side * side, 1e-8);  // float vertices
  const double expected = b.surface_area_m2 / (0.003 * 0.003);  // ~3871 points
  EXPECT_NEAR(static_cast<double>(b.surface_points.size()), expected, 3.0 * std::sqrt(expected));
  const Vec3 c = expected_centre(kFruitB);
  for (const Vec3& q : b.surface_points) {
    const Vec3 d = (q - c).cwiseAbs();
    ASSERT_NEAR(d.maxCoeff(), 0.5 * side, 1e-6);  // on the cube's surface (assimp holds floats)
  }
  // Same seed, same points; the fragment's area is part of fruit A.
  const ImportedPlant again = import_plant(write_collada("density2", true), o);
  EXPECT_EQ(again.truth.fruits[0].surface_points, p.truth.fruits[0].surface_points);
  EXPECT_NEAR(p.truth.fruits[0].surface_area_m2, 6 * side * side + 6 * std::pow(0.2 * kInch, 2), 1e-8);
}

TEST(PlantImport, VertexGroundTruthIsTheWeldedMeshVertices) {
  ImportOptions o = capsicum();
  o.truth = TruthMode::kVertices;
  const ImportedPlant p = import_plant(write_collada("vertices", true), o);
  EXPECT_EQ(p.truth.fruits[0].surface_points.size(), 16u);  // cube + fragment corners
  EXPECT_EQ(p.truth.fruits[1].surface_points.size(), 8u);
}

TEST(PlantImport, UnitInTheFileAndGeometryInstancedTwiceImportsTheSamePlantAndReportsDuplicates) {
  const ImportedPlant fresh = import_plant(write_collada("new2", true), capsicum());
  const ImportedPlant old = import_plant(write_collada("old", false), capsicum());
  EXPECT_DOUBLE_EQ(old.report.file_unit_m, kInch);
  EXPECT_DOUBLE_EQ(old.report.unit_scale, kInch);
  EXPECT_LT((old.report.size_m - fresh.report.size_m).norm(), 1e-6);
  EXPECT_EQ(old.report.triangles_in, 2 * fresh.report.triangles_in);  // once per instance, as the file says
  EXPECT_EQ(old.report.duplicate_triangles, fresh.report.triangles_in);
  ASSERT_EQ(old.report.duplicate_nodes.size(), 1u);
  EXPECT_EQ(old.report.duplicate_nodes[0], "plant_node = plant_node_copy");
  EXPECT_EQ(old.triangle_count(), 2 * fresh.triangle_count());
  ASSERT_EQ(old.truth.fruits.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {  // the ground truth counts the doubled surface once
    EXPECT_NEAR(old.truth.fruits[k].surface_area_m2, fresh.truth.fruits[k].surface_area_m2, 1e-9);
    EXPECT_LT((old.truth.fruits[k].center - fresh.truth.fruits[k].center).norm(), 1e-6);
  }
  // --unit-scale overrides the file's unit.
  ImportOptions o = capsicum();
  o.unit_scale = 0.01;
  const ImportedPlant cm = import_plant(write_collada("old_cm", false), o);
  EXPECT_NEAR(cm.report.size_m.z(), kHeightIn * 0.01, 1e-6);
  EXPECT_DOUBLE_EQ(cm.report.unit_scale, 0.01);
}

TEST(PlantImport, ObjWithMtlYUpMatchesTheCollada) {
  const std::string dir = temp_dir("obj");
  write_obj(dir + "/plant.obj", "plant.mtl");
  ImportOptions o = capsicum();
  o.up = "y";
  const ImportedPlant obj = import_plant(dir + "/plant.obj", o);
  const ImportedPlant dae = import_plant(write_collada("new3", true), capsicum());
  EXPECT_LT((obj.report.size_m - dae.report.size_m).norm(), 1e-6);
  ASSERT_EQ(obj.parts.size(), dae.parts.size());
  for (size_t i = 0; i < obj.parts.size(); ++i) {
    EXPECT_EQ(obj.parts[i].class_name, dae.parts[i].class_name);
    EXPECT_EQ(obj.parts[i].mesh.faces.size(), dae.parts[i].mesh.faces.size());
  }
  for (size_t k = 0; k < 2; ++k) EXPECT_LT((obj.truth.fruits[k].center - dae.truth.fruits[k].center).norm(), 1e-6);
  EXPECT_FLOAT_EQ(obj.parts[0].rgba[1], 0.6f);  // Kd from the MTL
  // Taken as Z-up, the same file lies on its side: the up axis comes from --up.
  o.up = "z";
  EXPECT_NEAR(import_plant(dir + "/plant.obj", o).report.size_m.z(), 3.0 * kInch, 1e-6);
}

TEST(PlantImport, UnripeMaterialsAreFruitInstancesThatAreNotTargets) {
  const ImportedPlant p = import_plant(write_collada("unripe", true, true), capsicum());
  ASSERT_EQ(p.truth.fruits.size(), 2u);
  // Fruits are numbered by material name: frt0 (B) before frt1 (A).
  const ImportedPart* b = fruit_part(p, 0);
  const ImportedPart* a = fruit_part(p, 1);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(b->material, "Capsicum_frt0");
  EXPECT_EQ(b->class_name, "fruit");
  EXPECT_FALSE(b->target);
  EXPECT_FALSE(p.truth.fruits[0].target);
  EXPECT_LT((p.truth.fruits[0].center - expected_centre(kFruitB)).norm(), 1e-6);
  EXPECT_TRUE(a->target && p.truth.fruits[1].target);
  // The same with a command-line rule before the preset, which wins.
  ImportOptions o = capsicum();
  o.rules.insert(o.rules.begin(), parse_class_rule("fruit:unripe=frt1"));
  const ImportedPlant q = import_plant(write_collada("unripe2", true, true), o);
  EXPECT_FALSE(q.truth.fruits[1].target);
  EXPECT_THROW(parse_class_rule("fruit:green=x"), InputError);
  EXPECT_THROW(parse_class_rule("fruit"), InputError);
}

TEST(PlantImport, BadFilesAndMappingsAreInputErrors) {
  const std::string dae = write_collada("bad", true);
  auto message = [](const std::string& path, const ImportOptions& o) {
    try {
      import_plant(path, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("/nonexistent/plant.dae", capsicum()).find("no such file"), std::string::npos);
  const std::string junk = temp_dir("junk") + "/junk.dae";
  write_text(junk, "<COLLADA><asset></COLLADA");
  EXPECT_NE(message(junk, capsicum()).find("assimp cannot read it"), std::string::npos);
  const std::string empty = temp_dir("empty") + "/empty.obj";
  write_text(empty, "# nothing\n");
  EXPECT_NE(message(empty, capsicum()).find(empty), std::string::npos);
  ImportOptions leaf_only;
  leaf_only.rules = {parse_class_rule("leaf=lef")};
  EXPECT_NE(message(dae, leaf_only).find("no --class rule matches the material(s) 'Capsicum_frt1'"), std::string::npos);
  leaf_only.fallback = parse_class_rule("leaf=.*");
  EXPECT_NE(message(dae, leaf_only).find("no material maps to the fruit class 'fruit'"), std::string::npos);
  ImportOptions bad_regex;
  bad_regex.rules = {parse_class_rule("fruit=frt(")};
  EXPECT_NE(message(dae, bad_regex).find("does not compile"), std::string::npos);
  ImportOptions scale = capsicum();
  scale.unit_scale = 0.0;
  EXPECT_NE(message(dae, scale).find("--unit-scale"), std::string::npos);
  ImportOptions budget = capsicum();
  budget.max_triangles = 30;  // the fruit alone has 36
  EXPECT_NE(message(dae, budget).find("--max-triangles is 30"), std::string::npos);
}

TEST(PlantImport, OverBudgetLeavesAreSimplifiedUntilTheyFit) {
  // A finely tessellated 30 x 5 cm leaf (5 mm cells, 1200 triangles) and one fruit cube.
  std::ostringstream obj;
  obj << "mtllib m.mtl\nusemtl lef\n";
  const int nx = 60, ny = 10;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) obj << "v " << 0.005 * i << " " << 0.005 * j << " " << 0.5 + 0.001 * std::sin(i) << "\n";
  auto id = [&](int i, int j) { return 1 + j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      obj << "f " << id(i, j) << " " << id(i + 1, j) << " " << id(i + 1, j + 1) << "\nf " << id(i, j) << " "
          << id(i + 1, j + 1) << " " << id(i, j + 1) << "\n";
  obj << "v 0 0 0\nv 0.002 0 0\nv 0 0.002 0.4\n" << "f -3 -2 -1\n";  // a stem sliver down to the ground
  obj << "usemtl frt1\n";
  int v0 = (nx + 1) * (ny + 1) + 4;
  for (const auto& t : cube({4, 4, 20}, 3)) {
    for (const auto& p : t) obj << "v " << p[0] * kInch << " " << p[1] * kInch << " " << p[2] * kInch << "\n";
    obj << "f " << v0 << " " << v0 + 1 << " " << v0 + 2 << "\n";
    v0 += 3;
  }
  const std::string dir = temp_dir("fine");
  write_text(dir + "/fine.obj", obj.str());
  write_text(dir + "/m.mtl", "newmtl lef\nKd 0.2 0.6 0.1\nnewmtl frt1\nKd 0.8 0.1 0.1\n");
  ImportOptions o = capsicum();
  const ImportedPlant full = import_plant(dir + "/fine.obj", o);
  EXPECT_EQ(full.triangle_count(), 1200 + 1 + 12);
  o.max_triangles = 300;
  const ImportedPlant small = import_plant(dir + "/fine.obj", o);
  EXPECT_LE(small.triangle_count(), 300);
  EXPECT_GT(small.report.simplify_cell_m, 0.0);
  EXPECT_EQ(fruit_part(small, 0)->mesh.faces.size(), 12u);  // fruit is never simplified
  EXPECT_LT((small.report.size_m - full.report.size_m).norm(), 0.02);  // the leaf keeps its extent
}

TEST(PlantImport, SavedFolderReadsBackAndWorldsPlaceItInSlotsAndAtPositions) {
  ImportOptions o = capsicum();
  const ImportedPlant p = import_plant(write_collada("save", true, true), o);
  const std::string dir = temp_dir("folder");
  p.save(dir);
  for (const char* f : {"plant.yaml", "fruits.json", "fruit_points.csv", "meshes/fruit_0.obj", "meshes/fruit_1.obj"})
    EXPECT_TRUE(fs::exists(dir + "/" + f)) << f;
  const PlantAsset a = load_plant_asset(dir);
  ASSERT_EQ(a.parts.size(), p.parts.size());
  for (size_t i = 0; i < a.parts.size(); ++i) {
    EXPECT_EQ(a.parts[i].mesh.faces.size(), p.parts[i].mesh.faces.size());
    EXPECT_NEAR(a.parts[i].mesh.area(), p.parts[i].mesh.area(), 1e-7);  // OBJ keeps float precision
    EXPECT_EQ(a.parts[i].fruit, p.parts[i].fruit);
    EXPECT_EQ(a.parts[i].target, p.parts[i].target);
  }
  EXPECT_NEAR(a.height_m, kHeightIn * kInch, 1e-6);
  ASSERT_EQ(a.truth.fruits.size(), 2u);
  EXPECT_EQ(a.truth.fruits[1].surface_points.size(), p.truth.fruits[1].surface_points.size());
  EXPECT_FALSE(a.truth.fruits[0].target);
  EXPECT_TRUE(a.truth.fruits[1].target);

  // A world: one imported plant in slot [0, 1] turned by 90 degrees, one at a free position.
  const std::string world_dir = temp_dir("world");
  const std::string base = "rows: {rows: 2, plants_per_row: 2, position_jitter_m: 0.02}\nseed: 5\n";
  write_text(world_dir + "/plain.yaml", base);
  write_text(world_dir + "/mixed.yaml", base + "plants:\n  - {plant: {import: " + dir +
                                            "}, slot: [0, 1], yaw_deg: 90}\n  - {plant: {import: " + dir +
                                            "}, position: [2.0, -0.9]}\n");
  const WorldSpec spec = WorldSpec::load(world_dir + "/mixed.yaml");
  EXPECT_EQ(spec.plant_count(), 5);
  const World w = generate_world(spec);
  const World plain = generate_world(WorldSpec::load(world_dir + "/plain.yaml"));
  ASSERT_EQ(w.plants.size(), 5u);
  EXPECT_EQ(w.plants[1].import_dir, fs::absolute(dir).lexically_normal().string());
  EXPECT_EQ(w.plants[0].parts[0].mesh.vertices, plain.plants[0].parts[0].mesh.vertices);  // procedural plants unchanged
  EXPECT_EQ(w.plants[3].parts[0].mesh.vertices, plain.plants[3].parts[0].mesh.vertices);
  const Vec3 slot(spec.rows.plant_spacing_m, spec.rows.row_offset_m, 0.0);
  EXPECT_EQ(w.plants[1].base_position, slot);
  EXPECT_EQ(w.plants[4].base_position, Vec3(2.0, -0.9, 0.0));
  // Instances continue the world's numbering; the folder's ground truth is placed with the plant.
  std::set<int> ids;
  for (const auto& f : w.truth.fruits) EXPECT_TRUE(ids.insert(f.instance_id).second);
  int imported = 0;
  for (const auto& f : w.truth.fruits) {
    if (f.plant_index != 1) continue;
    const FruitTruth& src = a.truth.fruits[static_cast<size_t>(imported++)];
    ASSERT_EQ(f.surface_points.size(), src.surface_points.size());
    const Vec3 q = src.surface_points[7];
    EXPECT_LT((f.surface_points[7] - (slot + Vec3(-q.y(), q.x(), q.z()))).norm(), 1e-9);  // yaw 90 degrees
    EXPECT_EQ(f.target, src.target);
  }
  EXPECT_EQ(imported, 2);
  for (const auto& part : w.plants[1].parts)
    EXPECT_EQ(part.class_id, spec.classes.index_of(part.instance_id == kNoInstance ? "leaf" : "fruit"));
  // Generated with its plants dropped: the imported plants stay held, the procedural ones are
  // made again (issue 49), the same world.
  GenerateOptions drop;
  drop.drop_plants_from_triangles = 0.0;
  const World dropped = generate_world(spec, drop);
  ASSERT_EQ(dropped.plants.size(), w.plants.size());
  for (std::size_t i = 0; i < w.plants.size(); ++i) {
    EXPECT_EQ(dropped.plants[i].held, !w.plants[i].import_dir.empty()) << i;
    canopy::test::expect_same_plant(*dropped.plant(i), w.plants[i]);
  }
  canopy::test::expect_same_truth(dropped.truth, w.truth);

  // Bad placements.
  auto load_error = [&](const std::string& text) {
    write_text(world_dir + "/bad.yaml", base + text);
    try {
      generate_world(WorldSpec::load(world_dir + "/bad.yaml"));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(load_error("plants: [{plant: {import: " + dir + "}, slot: [2, 0]}]\n").find("is not a slot"), std::string::npos);
  EXPECT_NE(load_error("plants: [{plant: {import: " + dir + "}, slot: [0, 0]}, {plant: {import: " + dir +
                       "}, slot: [0, 0]}]\n").find("taken twice"), std::string::npos);
  EXPECT_NE(load_error("plants: [{plant: {import: /nonexistent}, slot: [0, 0]}]\n").find("is not a plant folder"),
            std::string::npos);
  EXPECT_NE(load_error("plants: [{plant: {import: " + dir + "}}]\n").find("exactly one of"), std::string::npos);
  EXPECT_NE(load_error("plants: [{plant: {import: " + dir + "}, slot: [0, 0], yaw: 1}]\n").find("unknown key 'plants[0].yaw'"),
            std::string::npos);
  ImportOptions stems = capsicum();
  stems.rules.insert(stems.rules.begin(), parse_class_rule("stem=lef"));
  const std::string stem_dir = temp_dir("stem_folder");
  import_plant(write_collada("stem", true), stems).save(stem_dir);
  EXPECT_NE(load_error("plants: [{plant: {import: " + stem_dir + "}, slot: [0, 0]}]\n").find("class 'stem'"),
            std::string::npos);
}


// ---- textures -----------------------------------------------------------------------------

constexpr std::array<unsigned char, 3> kRed = {200, 30, 20}, kBlue = {20, 30, 200}, kGreen = {40, 160, 40};

// The textured plant (white diffuse colours, a TGA per material) in its own folder: fruit
// textures red in their top half (the part their UVs use) and blue below, unless
// `fruit_top` says otherwise; the leaf texture green.
std::string write_textured(const std::string& name, std::array<unsigned char, 3> fruit_top = kRed) {
  const std::string dir = temp_dir(name);
  write_text(dir + "/plant.dae", collada_textured(true));
  write_tga(dir + "/Capsicum_frt1.tga", 8, 8, 4, fruit_top, kBlue);
  write_tga(dir + "/Capsicum_frt0.tga", 8, 8, 4, {200, 200, 40}, kBlue);
  write_tga(dir + "/Capsicum_lef.tga", 8, 8, 8, kGreen, kGreen);
  return dir + "/plant.dae";
}

const MaterialReport* material(const ImportedPlant& p, const std::string& name) {
  for (const auto& m : p.report.materials)
    if (m.name == name) return &m;
  return nullptr;
}

TEST(PlantTexture, TexelWeightsCountTheTexelCentresUnderEachFaceAndWrap) {
  // The lower-left half of a 4 x 4 texture: texel centres (i + 0.5, j + 0.5) with i + j <= 3.
  const FaceUv half = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
  std::vector<double> w = texel_weights(4, 4, {half});
  double sum = 0.0;
  for (double x : w) sum += x;
  EXPECT_DOUBLE_EQ(sum, 10.0);
  EXPECT_EQ(w[3 * 4 + 0], 1.0);  // bottom-left texel: image row 3, column 0
  EXPECT_EQ(w[0 * 4 + 3], 0.0);  // top-right texel
  // The same face one repeat further covers the same texels.
  EXPECT_EQ(texel_weights(4, 4, {{Vec2(1, 2), Vec2(2, 2), Vec2(1, 3)}}), w);
  // A face holding no texel centre adds its area (in texels) under its centroid.
  w = texel_weights(4, 4, {{Vec2(0.30, 0.80), Vec2(0.32, 0.80), Vec2(0.30, 0.82)}});
  EXPECT_NEAR(w[0 * 4 + 1], 0.5 * 0.08 * 0.08, 1e-12);
  // Mean colour: a texture red on the left, blue on the right, under the left half only.
  Image<Rgb8> img(4, 4, Rgb8{0, 0, 255});
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 2; ++x) img.at(x, y) = Rgb8{255, 0, 0};
  const auto mean = mean_color(img, texel_weights(4, 4, {{Vec2(0, 0), Vec2(0.5, 0), Vec2(0.5, 1)}, {Vec2(0, 0), Vec2(0.5, 1), Vec2(0, 1)}}));
  EXPECT_FLOAT_EQ(mean[0], 1.f);
  EXPECT_FLOAT_EQ(mean[2], 0.f);
}

TEST(PlantTexture, DecodingRejectsWhatIsNoImage) {
  EXPECT_THROW(decode_image("not an image", "x.tga"), InputError);
  EXPECT_THROW(decode_image("", "x.tga"), InputError);
}

// Issue 31, item 15: a TGA cut short decoded with black fill; it is refused, as a cut PNG is.
TEST(PlantTexture, TruncatedTgaIsRefusedAndAWholeOneDecodes) {
  // 4 x 3 px, 24 bits, uncompressed (type 2) and run-length encoded (type 10), all red.
  auto header = [](char type) {
    std::string h(18, '\0');
    h[2] = type;
    h[12] = 4;
    h[14] = 3;
    h[16] = 24;
    return h;
  };
  std::string raw = header(2);
  for (int i = 0; i < 12; ++i) raw += std::string("\x00\x00\xff", 3);  // BGR
  const Image<Rgb8> whole = decode_image(raw, "red.tga");
  ASSERT_EQ(whole.width, 4);
  EXPECT_EQ(whole.data.back().r, 255);
  for (std::size_t cut : {std::size_t(20), raw.size() - 1}) {
    try {
      decode_image(raw.substr(0, cut), "red.tga");
      ADD_FAILURE() << "a TGA cut to " << cut << " bytes decoded";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("red.tga: truncated TGA"), std::string::npos) << e.what();
    }
  }
  std::string rle = header(10);
  for (int i = 0; i < 3; ++i) rle += std::string("\x83\x00\x00\xff", 4);  // a run of 4 red pixels per row
  EXPECT_EQ(decode_image(rle, "rle.tga").data.front().r, 255);
  EXPECT_THROW(decode_image(rle.substr(0, rle.size() - 4), "rle.tga"), InputError);
}

TEST(PlantImport, TexturedColladaKeepsItsTgaTexturesAndTextureCoordinatesThroughTheFolder) {
  const ImportedPlant p = import_plant(write_textured("textured"), capsicum());
  ASSERT_EQ(p.report.materials.size(), 3u);
  const MaterialReport* fruit = material(p, "Capsicum_frt1");
  ASSERT_TRUE(fruit);
  EXPECT_EQ(fruit->colour, "image");
  EXPECT_EQ(fruit->texture_source, "Capsicum_frt1.tga");
  EXPECT_EQ(fruit->texture_width, 8);
  // Its UVs cover only the red top half: the UV-weighted mean is the red, exactly.
  EXPECT_NEAR(fruit->rgba[0], kRed[0] / 255.0, 1e-6);
  EXPECT_NEAR(fruit->rgba[1], kRed[1] / 255.0, 1e-6);
  EXPECT_NEAR(fruit->rgba[2], kRed[2] / 255.0, 1e-6);
  for (const auto& part : p.parts) {
    ASSERT_TRUE(part.texture) << part.material;
    EXPECT_EQ(part.uv.size(), part.mesh.faces.size());
    EXPECT_EQ(part.rgba[0], 1.f);
    if (part.fruit < 0) continue;
    for (const auto& f : part.uv)
      for (const auto& t : f) {
        EXPECT_TRUE(t.y() >= 0.55 - 1e-6 && t.y() <= 0.95 + 1e-6) << t.transpose();
      }
  }
  for (const auto& w : p.report.warnings) EXPECT_EQ(w.find("texture"), std::string::npos) << w;

  const std::string dir = temp_dir("textured_folder");
  p.save(dir);
  const PlantAsset a = load_plant_asset(dir);
  ASSERT_EQ(a.parts.size(), p.parts.size());
  for (size_t i = 0; i < a.parts.size(); ++i) {
    const ImportedPart &in = p.parts[i], &out = a.parts[i];
    ASSERT_TRUE(out.texture);
    EXPECT_EQ(out.texture->data, in.texture->data);  // PNG is lossless
    ASSERT_EQ(out.uv.size(), in.uv.size());
    ASSERT_EQ(out.mesh.faces.size(), in.mesh.faces.size());
    for (size_t k = 0; k < out.uv.size(); ++k)
      for (size_t c = 0; c < 3; ++c) {
        EXPECT_NEAR((out.uv[k][c] - in.uv[k][c]).norm(), 0.0, 1e-6);
        EXPECT_NEAR((out.mesh.vertices[static_cast<size_t>(out.mesh.faces[k][c])] -
                     in.mesh.vertices[static_cast<size_t>(in.mesh.faces[k][c])]).norm(), 0.0, 1e-6);
      }
  }
  const YAML::Node y = YAML::LoadFile(dir + "/plant.yaml");
  EXPECT_EQ(y["texture_mode"].as<std::string>(), "image");
  EXPECT_EQ(y["materials"]["Capsicum_frt1"]["colour"].as<std::string>(), "image");
  EXPECT_EQ(y["materials"]["Capsicum_frt1"]["texture_source"].as<std::string>(), "Capsicum_frt1.tga");

  // A world places the textured plant with its texture and coordinates.
  const std::string world_dir = temp_dir("textured_world");
  write_text(world_dir + "/w.yaml", "rows: {rows: 1, plants_per_row: 1, position_jitter_m: 0.0}\nplants: [{plant: {import: " +
                                        dir + "}, slot: [0, 0]}]\n");
  const World w = generate_world(WorldSpec::load(world_dir + "/w.yaml"));
  for (const auto& part : w.plants[0].parts) {
    ASSERT_TRUE(part.texture);
    EXPECT_TRUE(fs::is_regular_file(part.texture_file)) << part.texture_file;
    EXPECT_EQ(part.uv.size(), part.mesh.faces.size());
  }
}

TEST(PlantImport, TextureMeanBakesTheUvWeightedMeanColourAndMissingTexturesAreReported) {
  ImportOptions o = capsicum();
  o.texture = TextureMode::kMean;
  const ImportedPlant p = import_plant(write_textured("mean"), o);
  for (const auto& part : p.parts) {
    EXPECT_FALSE(part.texture);
    EXPECT_TRUE(part.uv.empty());
    if (part.material == "Capsicum_frt1") {
      EXPECT_NEAR(part.rgba[0], kRed[0] / 255.0, 1e-6);
      EXPECT_NEAR(part.rgba[2], kRed[2] / 255.0, 1e-6);
    } else if (part.material == "Capsicum_lef") {
      EXPECT_NEAR(part.rgba[1], kGreen[1] / 255.0, 1e-6);
    }
  }
  EXPECT_EQ(material(p, "Capsicum_lef")->colour, "mean");
  const std::string dir = temp_dir("mean_folder");
  p.save(dir);
  EXPECT_FALSE(fs::exists(dir + "/textures"));
  std::ifstream obj(dir + "/meshes/fruit_1.obj");
  const std::string text((std::istreambuf_iterator<char>(obj)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find("vt "), std::string::npos);
  const PlantAsset a = load_plant_asset(dir);
  for (const auto& part : a.parts) EXPECT_FALSE(part.texture);

  // The leaf texture missing: flat colour, a warning naming it, "missing" in the report.
  const std::string path = write_textured("missing");
  fs::remove(fs::path(path).parent_path() / "Capsicum_lef.tga");
  const ImportedPlant m = import_plant(path, capsicum());
  EXPECT_EQ(material(m, "Capsicum_lef")->colour, "missing");
  bool warned = false;
  for (const auto& w : m.report.warnings) warned = warned || w.find("'Capsicum_lef.tga' is not found") != std::string::npos;
  EXPECT_TRUE(warned);
  // A texture that is no image is an input error naming the file.
  write_text((fs::path(path).parent_path() / "Capsicum_lef.tga").string(), "garbage");
  try {
    import_plant(path, capsicum());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Capsicum_lef.tga"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace canopy::world
