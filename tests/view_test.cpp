// mechgen view: the page in a real browser (headless Chromium: no console error, the bodies'
// poses read back from the page's three.js scene equal the sweep CSV's, a screenshot that shows
// the mechanism) and the glTF file against the glTF 2.0 specification (a structural validator of
// our own, then three.js's GLTFLoader in Chromium). The browser tests skip, saying why, where
// Chromium is not installed or cannot start (scripts/deps.sh installs it).
#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "report/csv_table.hpp"
#include "report/view_scene.hpp"

#ifndef MECHGEN_BINARY
#error "MECHGEN_BINARY must name the mechgen binary (tests/CMakeLists.txt)"
#endif

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
const std::string kSource = MECHGEN_SOURCE_DIR;
const std::string kMechgen = MECHGEN_BINARY;

struct Run {
  int status = -1;
  std::string out;
};

Run run(const std::string& command) {
  Run r;
  FILE* pipe = popen((command + " 2>/dev/null").c_str(), "r");
  if (!pipe) return r;
  char buffer[65536];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.out.append(buffer, n);
  r.status = pclose(pipe);
  return r;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "mechgen_view_XXXXXX").string();
    path_ = mkdtemp(pattern.data()) ? pattern : "";
  }
  ~TempDir() {
    std::error_code e;
    if (!path_.empty()) fs::remove_all(path_, e);
  }
  fs::path operator/(const std::string& name) const { return fs::path(path_) / name; }

 private:
  std::string path_;
};

// Headless Chromium with software WebGL (SwiftShader): works without a GPU or a display.
const char* const kChromium =
    "chromium --headless --no-sandbox --disable-gpu --use-angle=swiftshader "
    "--enable-unsafe-swiftshader --no-first-run --disable-extensions --user-data-dir=";

// Empty when Chromium starts; else why not.
std::string chromium_problem(const TempDir& dir) {
  static std::string problem = [&] {
    if (std::system("command -v chromium >/dev/null 2>&1") != 0)
      return std::string("chromium is not installed (bash scripts/deps.sh installs it)");
    const Run r = run(std::string("timeout 60 ") + kChromium + (dir / "profile").string() +
                      " --dump-dom about:blank");
    if (r.status != 0 || r.out.find("<body") == std::string::npos)
      return std::string("chromium does not start headless here");
    return std::string();
  }();
  return problem;
}

// The page's DOM after load, as headless Chromium dumps it.
std::string dump_dom(const TempDir& dir, const fs::path& page, const std::string& fragment) {
  return run(std::string("timeout 120 ") + kChromium + (dir / "profile").string() +
             " --virtual-time-budget=5000 --dump-dom 'file://" + page.string() + fragment + "'")
      .out;
}

// The JSON the page writes into <pre id="mechgen-test"> (text content, HTML-unescaped).
json test_output(const std::string& dom) {
  const std::string open = "<pre id=\"mechgen-test\" hidden=\"\">";
  const size_t a = dom.find(open);
  if (a == std::string::npos) return json();
  const size_t b = dom.find("</pre>", a);
  std::string text = dom.substr(a + open.size(), b - a - open.size()), plain;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, 5, "&amp;") == 0)
      plain += '&', i += 4;
    else if (text.compare(i, 4, "&lt;") == 0)
      plain += '<', i += 3;
    else if (text.compare(i, 4, "&gt;") == 0)
      plain += '>', i += 3;
    else
      plain += text[i];
  }
  return plain.empty() ? json() : json::parse(plain, nullptr, false);
}

std::string model(const std::string& name) {
  return kSource + "/models/" + name + ".yaml";
}

// Seeks the page to rows of the CSV and compares every moving body's pose the scene holds with
// the row's (planar: x, y, th; spatial: x, y, z, qw..qz) to 1e-9.
void expect_scene_matches_csv(const TempDir& dir, const fs::path& page, const fs::path& csv,
                              bool spatial, const std::vector<size_t>& rows) {
  const mechgen::report::CsvTable table = mechgen::report::read_csv(csv.string());
  std::string fragment = "#test=";
  for (const size_t r : rows) {
    char t[40];
    std::snprintf(t, sizeof t, "%.17g,", table.rows[r][0]);
    fragment += t;
  }
  const json out = test_output(dump_dom(dir, page, fragment));
  ASSERT_TRUE(out.is_object()) << "the page wrote no test output";
  EXPECT_TRUE(out["webgl"].get<bool>());
  EXPECT_TRUE(out["errors"].empty()) << out["errors"].dump();
  ASSERT_EQ(out["readings"].size(), rows.size());
  int compared = 0;
  for (size_t k = 0; k < rows.size(); ++k) {
    const std::vector<double>& row = table.rows[rows[k]];
    for (const auto& [name, pose] : out["readings"][k]["bodies"].items()) {
      const int x = table.column(name + ".x");
      if (x < 0) continue;  // the fixed ground
      auto at = [&](const std::string& suffix) {
        return row[static_cast<size_t>(table.require_column(name + suffix))];
      };
      const std::vector<double> p = pose["p"], q = pose["q"];
      std::vector<double> want_p, want_q;
      if (spatial) {
        want_p = {at(".x"), at(".y"), at(".z")};
        want_q = {at(".qw"), at(".qx"), at(".qy"), at(".qz")};
      } else {
        const mechgen::report::Quat r = mechgen::report::planar_rotation(at(".th"));
        want_p = {at(".x"), at(".y"), 0.0};
        want_q = {r[0], r[1], r[2], r[3]};
      }
      for (size_t i = 0; i < 3; ++i)
        EXPECT_NEAR(p[i], want_p[i], 1e-9) << name << " row " << rows[k];
      for (size_t i = 0; i < 4; ++i)
        EXPECT_NEAR(q[i], want_q[i], 1e-9) << name << " row " << rows[k];
      ++compared;
    }
  }
  EXPECT_GE(compared, static_cast<int>(rows.size()) * 3);
}

TEST(ViewInBrowser, PlanarPosesInTheSceneAreTheSweepCsvs) {
  TempDir dir;
  if (const std::string why = chromium_problem(dir); !why.empty()) GTEST_SKIP() << why;
  const fs::path csv = dir / "sweep.csv", page = dir / "view.html";
  ASSERT_EQ(
      run(kMechgen + " sweep " + model("chebyshev") + " --samples 41 --out " + csv.string()).status,
      0);
  ASSERT_EQ(run(kMechgen + " view " + model("chebyshev") + " --csv " + csv.string() +
                " --trace P --out " + page.string())
                .status,
            0);
  expect_scene_matches_csv(dir, page, csv, false, {0, 7, 23, 40});
}

TEST(ViewInBrowser, SpatialPosesInTheSceneAreTheSweepCsvs) {
  TempDir dir;
  if (const std::string why = chromium_problem(dir); !why.empty()) GTEST_SKIP() << why;
  const fs::path csv = dir / "sweep.csv", page = dir / "view.html";
  ASSERT_EQ(run(kMechgen + " sweep " + model("rsur") + " --solver numeric --samples 31 --out " +
                csv.string())
                .status,
            0);
  ASSERT_EQ(run(kMechgen + " view " + model("rsur") + " --csv " + csv.string() + " --out " +
                page.string())
                .status,
            0);
  expect_scene_matches_csv(dir, page, csv, true, {0, 11, 30});
}

// The seed systems the issue names open and show their own tables: PASIBOT walking over several
// steps (planar), the quadruped leg along its swing (spatial, the generated kernel's sweep) and
// the Bioloid's gait (humanoid-gait's gait.csv, the body poses of the whole walk).
TEST(ViewInBrowser, SeedSystemsShowTheirTables) {
  const auto first_middle_last = [](const fs::path& csv) {
    const size_t n = mechgen::report::read_csv(csv.string()).rows.size();
    return std::vector<size_t>{0, n / 2, n - 1};
  };
  TempDir dir;
  if (const std::string why = chromium_problem(dir); !why.empty()) GTEST_SKIP() << why;
  const fs::path pasibot = dir / "pasibot.csv", leg = dir / "leg.csv", page = dir / "view.html";
  ASSERT_EQ(run(kMechgen + " walk " + model("pasibot") + " --steps 3 --samples 40 --out " +
                pasibot.string())
                .status,
            0);
  ASSERT_EQ(run(kMechgen + " view " + model("pasibot") + " --csv " + pasibot.string() + " --out " +
                page.string())
                .status,
            0);
  expect_scene_matches_csv(dir, page, pasibot, false, first_middle_last(pasibot));
  ASSERT_EQ(run(kMechgen + " sweep " + model("quadruped_leg_swing") + " --samples 41 --out " +
                leg.string())
                .status,
            0);
  ASSERT_EQ(run(kMechgen + " view " + model("quadruped_leg_swing") + " --csv " + leg.string() +
                " --trace D --out " + page.string())
                .status,
            0);
  expect_scene_matches_csv(dir, page, leg, true, first_middle_last(leg));
  const fs::path gait = dir / "gait";
  fs::create_directories(gait);
  ASSERT_EQ(run(kMechgen + " humanoid-gait " + model("bioloid") + " --samples-per-step 8 --out " +
                gait.string())
                .status,
            0);
  ASSERT_EQ(run(kMechgen + " view " + model("bioloid") + " --csv " + (gait / "gait.csv").string() +
                " --out " + page.string())
                .status,
            0);
  expect_scene_matches_csv(dir, page, gait / "gait.csv", true,
                           first_middle_last(gait / "gait.csv"));
}

// Pixels of the PNG (RGB) and its size.
bool read_png(const fs::path& path, std::vector<unsigned char>& rgb, int& width, int& height) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return false;
  image.format = PNG_FORMAT_RGB;
  rgb.resize(PNG_IMAGE_SIZE(image));
  width = static_cast<int>(image.width);
  height = static_cast<int>(image.height);
  return png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr) != 0;
}

TEST(ViewInBrowser, ScreenshotShowsTheMechanism) {
  TempDir dir;
  if (const std::string why = chromium_problem(dir); !why.empty()) GTEST_SKIP() << why;
  const fs::path page = dir / "view.html", shot = dir / "shot.png";
  ASSERT_EQ(
      run(kMechgen + " view " + model("slider_crank") + " --samples 21 --out " + page.string())
          .status,
      0);
  run(std::string("timeout 120 ") + kChromium + (dir / "profile").string() +
      " --window-size=900,500 --virtual-time-budget=3000 --screenshot=" + shot.string() +
      " 'file://" + page.string() + "#t=0.01'");
  std::vector<unsigned char> rgb;
  int w = 0, h = 0;
  ASSERT_TRUE(read_png(shot, rgb, w, h)) << "no screenshot";
  ASSERT_EQ(w, 900);
  // The 3D view is the left two thirds above the control bar: count coloured pixels there (the
  // links are saturated colours; the floor grid is grey and the frame's axes are thin lines).
  int coloured = 0, painted = 0;
  for (int y = 0; y < h - 60; ++y)
    for (int x = 0; x < w * 6 / 10; ++x) {
      const unsigned char* p = &rgb[static_cast<size_t>(3 * (y * w + x))];
      const int hi = std::max({p[0], p[1], p[2]}), lo = std::min({p[0], p[1], p[2]});
      if (hi - lo > 60) ++coloured;
      if (lo < 235) ++painted;
    }
  EXPECT_GT(coloured, 1500) << "the links are not drawn";
  EXPECT_GT(painted, coloured);
}

// ---- glTF: a structural validator of the glTF 2.0 rules mechgen's files must meet ------------

std::uint32_t u32(const std::string& s, size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i)
    v = v << 8 | static_cast<unsigned char>(s[at + static_cast<size_t>(i)]);
  return v;
}

struct Glb {
  json doc;
  std::string bin;
};

// Checks the GLB container and the JSON's references; returns both chunks.
Glb validate_glb(const std::string& file) {
  Glb g;
  EXPECT_GE(file.size(), 28u);
  if (file.size() < 28) return g;
  EXPECT_EQ(u32(file, 0), 0x46546C67u) << "magic";
  EXPECT_EQ(u32(file, 4), 2u) << "version";
  EXPECT_EQ(u32(file, 8), file.size()) << "total length";
  const std::uint32_t json_length = u32(file, 12);
  EXPECT_EQ(u32(file, 16), 0x4E4F534Au) << "first chunk is JSON";
  EXPECT_EQ(json_length % 4, 0u);
  const size_t bin_at = 20 + json_length;
  EXPECT_LE(bin_at + 8, file.size());
  if (bin_at + 8 > file.size()) return g;
  const std::uint32_t bin_length = u32(file, bin_at);
  EXPECT_EQ(u32(file, bin_at + 4), 0x004E4942u) << "second chunk is BIN";
  EXPECT_EQ(bin_length % 4, 0u);
  EXPECT_EQ(bin_at + 8 + bin_length, file.size());
  g.doc = json::parse(file.substr(20, json_length), nullptr, false);
  EXPECT_FALSE(g.doc.is_discarded()) << "the JSON chunk does not parse";
  g.bin = file.substr(bin_at + 8, bin_length);
  const json& d = g.doc;
  EXPECT_EQ(d["asset"]["version"], "2.0");
  EXPECT_EQ(d["buffers"].size(), 1u);
  const size_t buffer_length = d["buffers"][0]["byteLength"];
  EXPECT_LE(buffer_length, bin_length);
  EXPECT_GT(buffer_length + 4, bin_length);  // padding only
  for (const json& v : d["bufferViews"]) {
    const size_t offset = v.value("byteOffset", 0), length = v["byteLength"];
    EXPECT_EQ(v["buffer"], 0);
    EXPECT_LE(offset + length, buffer_length);
    EXPECT_EQ(offset % 4, 0u);
  }
  for (const json& a : d["accessors"]) {
    const size_t view = a["bufferView"];
    EXPECT_LT(view, d["bufferViews"].size());
    EXPECT_EQ(a["componentType"], 5126);  // FLOAT
    const std::string type = a["type"];
    const size_t components = type == "SCALAR" ? 1 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 0;
    EXPECT_GT(components, 0u) << type;
    const size_t count = a["count"];
    EXPECT_GT(count, 0u);
    EXPECT_LE(a.value("byteOffset", 0) + count * components * 4,
              static_cast<size_t>(d["bufferViews"][view]["byteLength"]));
    if (a.contains("min")) {  // min and max are the data's
      const json& bv = d["bufferViews"][view];
      const float* data = reinterpret_cast<const float*>(g.bin.data() + bv.value("byteOffset", 0));
      for (size_t c = 0; c < components; ++c) {
        float lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < count; ++i)
          lo = std::min(lo, data[i * components + c]), hi = std::max(hi, data[i * components + c]);
        EXPECT_FLOAT_EQ(a["min"][c].get<float>(), lo);
        EXPECT_FLOAT_EQ(a["max"][c].get<float>(), hi);
      }
    }
  }
  for (const json& m : d["meshes"])
    for (const json& p : m["primitives"]) {
      const size_t position = p["attributes"]["POSITION"];
      EXPECT_TRUE(d["accessors"][position].contains("min")) << "POSITION needs min and max";
      const size_t count = d["accessors"][position]["count"];
      const int mode = p["mode"];
      EXPECT_EQ(count % (mode == 4 ? 3 : 2), 0u);
      if (p["attributes"].contains("NORMAL")) {
        EXPECT_EQ(d["accessors"][static_cast<size_t>(p["attributes"]["NORMAL"])]["count"], count);
      }
      EXPECT_LT(static_cast<size_t>(p["material"]), d["materials"].size());
    }
  for (const json& n : d["nodes"]) {
    if (n.contains("mesh")) {
      EXPECT_LT(static_cast<size_t>(n["mesh"]), d["meshes"].size());
    }
    for (const json& c : n.value("children", json::array()))
      EXPECT_LT(static_cast<size_t>(c), d["nodes"].size());
  }
  for (const json& a : d.value("animations", json::array())) {
    for (const json& s : a["samplers"]) {
      const json& in = d["accessors"][static_cast<size_t>(s["input"])];
      const json& out = d["accessors"][static_cast<size_t>(s["output"])];
      EXPECT_EQ(in["count"], out["count"]);
      EXPECT_GE(in["min"][0].get<double>(), 0.0);
      const float* t = reinterpret_cast<const float*>(
          g.bin.data() +
          d["bufferViews"][static_cast<size_t>(in["bufferView"])].value("byteOffset", 0));
      for (size_t i = 1; i < in["count"]; ++i)
        EXPECT_GT(t[i], t[i - 1]) << "times strictly increase";
    }
    for (const json& c : a["channels"]) {
      EXPECT_LT(static_cast<size_t>(c["sampler"]), a["samplers"].size());
      EXPECT_LT(static_cast<size_t>(c["target"]["node"]), d["nodes"].size());
    }
  }
  return g;
}

// The animation's key k of a node's translation or rotation.
std::vector<float> key(const Glb& g, int node, const std::string& path, size_t k) {
  const json& d = g.doc;
  for (const json& c : d["animations"][0]["channels"])
    if (c["target"]["node"] == node && c["target"]["path"] == path) {
      const json& s = d["animations"][0]["samplers"][static_cast<size_t>(c["sampler"])];
      const json& a = d["accessors"][static_cast<size_t>(s["output"])];
      const size_t n = a["type"] == "VEC3" ? 3 : 4;
      const float* v = reinterpret_cast<const float*>(
          g.bin.data() +
          d["bufferViews"][static_cast<size_t>(a["bufferView"])].value("byteOffset", 0));
      return std::vector<float>(v + n * k, v + n * (k + 1));
    }
  return {};
}

TEST(ViewGltf, SpatialSweepIsAValidAnimatedGlb) {
  TempDir dir;
  const fs::path csv = dir / "sweep.csv", glb = dir / "rsur.glb";
  ASSERT_EQ(run(kMechgen + " sweep " + model("rsur") + " --solver numeric --samples 21 --out " +
                csv.string())
                .status,
            0);
  ASSERT_EQ(run(kMechgen + " view " + model("rsur") + " --csv " + csv.string() + " --gltf " +
                glb.string())
                .status,
            0);
  const Glb g = validate_glb(read_file(glb));
  ASSERT_TRUE(g.doc.is_object());
  const mechgen::report::CsvTable table = mechgen::report::read_csv(csv.string());
  // Every moving body's keys are the CSV's poses (float32), rotation as x, y, z, w.
  int bodies = 0;
  for (size_t n = 0; n < g.doc["nodes"].size(); ++n) {
    const std::string name = g.doc["nodes"][n]["name"];
    if (table.column(name + ".x") < 0) continue;
    ++bodies;
    for (const size_t k : {size_t{0}, size_t{10}, size_t{20}}) {
      const std::vector<float> p = key(g, static_cast<int>(n), "translation", k);
      const std::vector<float> q = key(g, static_cast<int>(n), "rotation", k);
      ASSERT_EQ(p.size(), 3u);
      ASSERT_EQ(q.size(), 4u);
      auto at = [&](const char* s) {
        return table.rows[k][static_cast<size_t>(table.require_column(name + s))];
      };
      EXPECT_NEAR(p[0], at(".x"), 1e-6);
      EXPECT_NEAR(p[1], at(".y"), 1e-6);
      EXPECT_NEAR(p[2], at(".z"), 1e-6);
      // The same rotation (q or -q: keys keep the sign of the previous one).
      const double dot = q[0] * at(".qx") + q[1] * at(".qy") + q[2] * at(".qz") + q[3] * at(".qw");
      EXPECT_NEAR(std::abs(dot), 1.0, 1e-6) << name << " key " << k;
    }
  }
  EXPECT_EQ(bodies, 3);  // rsur's three moving links
}

TEST(ViewGltf, PlanarWalkRepeatedTimesKeepStrictlyIncreasingKeys) {
  TempDir dir;
  const fs::path glb = dir / "walk.glb";
  ASSERT_EQ(
      run(kMechgen + " view " + model("pasibot") + " --steps 2 --gltf " + glb.string()).status, 0);
  const Glb g = validate_glb(read_file(glb));
  ASSERT_TRUE(g.doc.contains("animations"));
  EXPECT_FALSE(g.doc["animations"][0]["channels"].empty());
}

// three.js's own GLTFLoader (Debian libjs-three) parses the file: its nodes and animation.
TEST(ViewGltf, ThreeJsGltfLoaderOpensIt) {
  TempDir dir;
  if (const std::string why = chromium_problem(dir); !why.empty()) GTEST_SKIP() << why;
  const fs::path csv = dir / "sweep.csv", glb = dir / "rsur.glb", page = dir / "load.html";
  ASSERT_EQ(run(kMechgen + " sweep " + model("rsur") + " --solver numeric --samples 21 --out " +
                csv.string())
                .status,
            0);
  ASSERT_EQ(run(kMechgen + " view " + model("rsur") + " --csv " + csv.string() + " --gltf " +
                glb.string())
                .status,
            0);
  const std::string bytes = read_file(glb);
  std::string list;  // the file as a JS byte array (no fetch from a file:// page)
  for (const char c : bytes) list += std::to_string(static_cast<unsigned char>(c)) + ",";
  const std::string three = "/usr/share/javascript/three";
  std::ofstream(page)
      << "<html><body><pre id=\"mechgen-test\" hidden></pre><script>"
      << read_file(three + "/three.min.js") << "</script><script>"
      << read_file(three + "/examples/js/loaders/GLTFLoader.js") << "</script><script>"
      << "var bytes = new Uint8Array([" << list << "]);"
      << "new THREE.GLTFLoader().parse(bytes.buffer, '', function (gltf) {"
      << "  var names = []; gltf.scene.traverse(function (o) { if (o.name) names.push(o.name); });"
      << "  document.getElementById('mechgen-test').textContent = JSON.stringify({"
      << "    names: names, animations: gltf.animations.length,"
      << "    tracks: gltf.animations.length ? gltf.animations[0].tracks.length : 0,"
      << "    duration: gltf.animations.length ? gltf.animations[0].duration : 0});"
      << "}, function (e) { document.getElementById('mechgen-test').textContent ="
      << "  JSON.stringify({error: String(e)}); });</script></body></html>";
  const json out = test_output(dump_dom(dir, page, ""));
  ASSERT_TRUE(out.is_object()) << "GLTFLoader wrote nothing";
  ASSERT_FALSE(out.contains("error")) << out["error"];
  EXPECT_EQ(out["animations"], 1);
  EXPECT_EQ(out["tracks"], 6);  // translation and rotation of 3 moving links
  const mechgen::report::CsvTable table = mechgen::report::read_csv(csv.string());
  EXPECT_NEAR(out["duration"].get<double>(), table.rows.back()[0], 1e-6);
  for (const char* body : {"mechanism"})
    EXPECT_NE(out["names"].dump().find(body), std::string::npos);
}

}  // namespace
