#include "report/gltf_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace mechgen::report {

namespace {

using Tri = std::vector<Vec3>;  // three vertices per triangle

Vec3 add(const Vec3& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec3 sub(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3 mul(double s, const Vec3& a) {
  return {s * a[0], s * a[1], s * a[2]};
}
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3& a) {
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}
Vec3 rotate(const Quat& q, const Vec3& v) {  // q v q*
  const Vec3 u{q[1], q[2], q[3]};
  const Vec3 t = mul(2, cross(u, v));
  return add(add(v, mul(q[0], t)), cross(u, t));
}

void quad(Tri& t, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  t.insert(t.end(), {a, b, c, a, c, d});
}

Tri box_triangles(const ViewShape& s) {
  Tri t;
  auto corner = [&](int i, int j, int k) {
    return add(s.center,
               rotate(s.rotation, {(i ? 0.5 : -0.5) * s.size[0], (j ? 0.5 : -0.5) * s.size[1],
                                   (k ? 0.5 : -0.5) * s.size[2]}));
  };
  quad(t, corner(0, 0, 0), corner(0, 1, 0), corner(1, 1, 0), corner(1, 0, 0));  // -z
  quad(t, corner(0, 0, 1), corner(1, 0, 1), corner(1, 1, 1), corner(0, 1, 1));  // +z
  quad(t, corner(0, 0, 0), corner(1, 0, 0), corner(1, 0, 1), corner(0, 0, 1));  // -y
  quad(t, corner(0, 1, 0), corner(0, 1, 1), corner(1, 1, 1), corner(1, 1, 0));  // +y
  quad(t, corner(0, 0, 0), corner(0, 0, 1), corner(0, 1, 1), corner(0, 1, 0));  // -x
  quad(t, corner(1, 0, 0), corner(1, 1, 0), corner(1, 1, 1), corner(1, 0, 1));  // +x
  return t;
}

Tri cylinder_triangles(const ViewShape& s, int segments = 16) {
  const Vec3 axis = sub(s.b, s.a);
  const double length = norm(axis);
  Tri t;
  if (!(length > 0)) return t;
  const Vec3 w = mul(1 / length, axis);
  Vec3 u = std::abs(w[0]) < 0.9 ? cross(w, {1, 0, 0}) : cross(w, {0, 1, 0});
  u = mul(1 / norm(u), u);
  const Vec3 v = cross(w, u);
  for (int i = 0; i < segments; ++i) {
    const double a0 = 2 * std::numbers::pi * i / segments,
                 a1 = 2 * std::numbers::pi * (i + 1) / segments;
    const Vec3 r0 = add(mul(s.radius * std::cos(a0), u), mul(s.radius * std::sin(a0), v));
    const Vec3 r1 = add(mul(s.radius * std::cos(a1), u), mul(s.radius * std::sin(a1), v));
    quad(t, add(s.a, r0), add(s.a, r1), add(s.b, r1), add(s.b, r0));
    t.insert(t.end(), {s.a, add(s.a, r1), add(s.a, r0), s.b, add(s.b, r0), add(s.b, r1)});
  }
  return t;
}

Tri sphere_triangles(const ViewShape& s, int rings = 8, int segments = 12) {
  Tri t;
  auto at = [&](int i, int j) {
    const double th = std::numbers::pi * i / rings, ph = 2 * std::numbers::pi * j / segments;
    return add(s.center, mul(s.radius, {std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                                        std::cos(th)}));
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j)
      quad(t, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
  return t;
}

// A plate: its polygon (ear clipping, either orientation) on both faces and its side walls.
Tri plate_triangles(const ViewShape& s) {
  std::vector<Vec3> p = s.outline;
  Tri t;
  if (p.size() < 3) return t;
  double area = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec3& a = p[i];
    const Vec3& b = p[(i + 1) % p.size()];
    area += a[0] * b[1] - b[0] * a[1];
  }
  if (area < 0) std::reverse(p.begin(), p.end());
  const double h = s.thickness / 2;
  auto up = [&](const Vec3& a) { return Vec3{a[0], a[1], a[2] + h}; };
  auto down = [&](const Vec3& a) { return Vec3{a[0], a[1], a[2] - h}; };
  auto turn = [](const Vec3& a, const Vec3& b, const Vec3& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  };
  for (size_t i = 0; i < p.size(); ++i)
    quad(t, down(p[i]), down(p[(i + 1) % p.size()]), up(p[(i + 1) % p.size()]), up(p[i]));
  std::vector<Vec3> left = p;
  while (left.size() > 3) {
    bool clipped = false;
    for (size_t i = 0; i < left.size() && !clipped; ++i) {
      const Vec3& a = left[(i + left.size() - 1) % left.size()];
      const Vec3& b = left[i];
      const Vec3& c = left[(i + 1) % left.size()];
      if (turn(a, b, c) <= 0) continue;  // a reflex corner is no ear
      bool inside = false;
      for (const Vec3& q : left)
        if (&q != &a && &q != &b && &q != &c && turn(a, b, q) > 0 && turn(b, c, q) > 0 &&
            turn(c, a, q) > 0)
          inside = true;
      if (inside) continue;
      t.insert(t.end(), {up(a), up(b), up(c), down(a), down(c), down(b)});
      left.erase(left.begin() + static_cast<long>(i));
      clipped = true;
    }
    if (!clipped) break;  // degenerate (collinear) remainder
  }
  if (left.size() == 3)
    t.insert(t.end(),
             {up(left[0]), up(left[1]), up(left[2]), down(left[0]), down(left[2]), down(left[1])});
  return t;
}

// ---- the binary buffer and the JSON text
// ---------------------------------------------------------

struct Writer {
  std::string bin;
  std::string views, accessors;
  int view_count = 0, accessor_count = 0;

  // Floats as one buffer view and one accessor; returns the accessor's index.
  int floats(const std::vector<float>& data, int components, bool bounds, int target) {
    const size_t offset = bin.size();
    bin.append(reinterpret_cast<const char*>(data.data()), data.size() * sizeof(float));
    views += std::string(view_count ? "," : "") +
             "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
             ",\"byteLength\":" + std::to_string(data.size() * 4) +
             (target ? ",\"target\":" + std::to_string(target) : "") + "}";
    const char* type = components == 1 ? "SCALAR" : components == 3 ? "VEC3" : "VEC4";
    std::string a = std::string(accessor_count ? "," : "") +
                    "{\"bufferView\":" + std::to_string(view_count) +
                    ",\"componentType\":5126,\"count\":" +
                    std::to_string(data.size() / static_cast<size_t>(components)) + ",\"type\":\"" +
                    type + "\"";
    if (bounds) {
      std::vector<float> lo(static_cast<size_t>(components), INFINITY), hi(lo.size(), -INFINITY);
      for (size_t i = 0; i < data.size(); ++i) {
        lo[i % lo.size()] = std::min(lo[i % lo.size()], data[i]);
        hi[i % lo.size()] = std::max(hi[i % lo.size()], data[i]);
      }
      auto list = [](const std::vector<float>& v) {
        std::string s = "[";
        for (size_t i = 0; i < v.size(); ++i) {
          char b[32];
          std::snprintf(b, sizeof b, "%.9g", static_cast<double>(v[i]));
          s += (i ? "," : "") + std::string(b);
        }
        return s + "]";
      };
      a += ",\"min\":" + list(lo) + ",\"max\":" + list(hi);
    }
    accessors += a + "}";
    ++view_count;
    return accessor_count++;
  }
};

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out + "\"";
}

std::string colour(int body, bool ground) {
  static const double palette[][3] = {{0.85, 0.37, 0.01}, {0.12, 0.47, 0.71}, {0.17, 0.63, 0.17},
                                      {0.58, 0.40, 0.74}, {0.91, 0.16, 0.54}, {0.55, 0.34, 0.29},
                                      {0.09, 0.75, 0.81}, {0.74, 0.74, 0.13}, {0.46, 0.44, 0.70},
                                      {0.90, 0.67, 0.01}};
  const double* c = ground ? palette[0] : palette[body % 10];
  char b[96];
  std::snprintf(b, sizeof b, "%.3g,%.3g,%.3g", ground ? 0.47 : c[0], ground ? 0.47 : c[1],
                ground ? 0.47 : c[2]);
  return b;
}

}  // namespace

std::string gltf_binary(const ViewScene& scene) {
  Writer w;
  std::string meshes, materials, nodes, channels, samplers;
  int mesh_count = 0, sampler_count = 0;
  // Materials: per body (solid, translucent inertia box), one for joints, one for lines.
  std::vector<std::string> material_list{
      "{\"name\":\"joint\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.33,0.33,0.33,1],"
      "\"metallicFactor\":0.3,\"roughnessFactor\":0.5}}",
      "{\"name\":\"line\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.15,0.15,0.15,1],"
      "\"metallicFactor\":0,\"roughnessFactor\":1}}"};
  // Animation keys: strictly increasing times, the later row of a repeated time.
  std::vector<size_t> keys;
  for (size_t i = 0; i < scene.times.size(); ++i) {
    // A time not after the previous key's in float32 replaces that key.
    if (!keys.empty() &&
        !(static_cast<float>(scene.times[i]) > static_cast<float>(scene.times[keys.back()])))
      keys.pop_back();
    keys.push_back(i);
  }
  const double shift = scene.times.empty() || scene.times.front() >= 0 ? 0 : -scene.times.front();
  int times_accessor = -1;
  if (keys.size() >= 2) {
    std::vector<float> t;
    for (const size_t k : keys) t.push_back(static_cast<float>(scene.times[k] + shift));
    times_accessor = w.floats(t, 1, true, 0);
  }
  std::string children;
  int node_count = 1;  // node 0: the root
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const ViewBody& body = scene.bodies[b];
    const std::string rgb = colour(static_cast<int>(b), body.ground);
    const int solid = static_cast<int>(material_list.size());
    material_list.push_back("{\"name\":" + json_string(body.name) +
                            ",\"pbrMetallicRoughness\":{\"baseColorFactor\":[" + rgb +
                            ",1],\"metallicFactor\":0.05,\"roughnessFactor\":0.6}}");
    material_list.push_back(
        "{\"name\":" + json_string(body.name + " (mass)") +
        ",\"alphaMode\":\"BLEND\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[" + rgb +
        ",0.45],\"metallicFactor\":0,\"roughnessFactor\":0.6}}");
    std::string primitives;
    std::vector<float> lines;
    for (const ViewShape& s : body.shapes) {
      if (s.kind == ViewShape::Kind::line) {
        for (size_t i = 0; i + 1 < s.outline.size(); ++i)
          for (const Vec3& p : {s.outline[i], s.outline[i + 1]})
            for (const double x : p) lines.push_back(static_cast<float>(x));
        continue;
      }
      const Tri tri = s.kind == ViewShape::Kind::box        ? box_triangles(s)
                      : s.kind == ViewShape::Kind::cylinder ? cylinder_triangles(s)
                      : s.kind == ViewShape::Kind::sphere   ? sphere_triangles(s)
                                                            : plate_triangles(s);
      std::vector<float> position, normal;
      for (size_t i = 0; i + 2 < tri.size(); i += 3) {
        Vec3 n = cross(sub(tri[i + 1], tri[i]), sub(tri[i + 2], tri[i]));
        const double l = norm(n);
        if (!(l > 0)) continue;  // a degenerate triangle (a cap's centre on a zero radius)
        n = mul(1 / l, n);
        for (int k = 0; k < 3; ++k)
          for (int c = 0; c < 3; ++c) {
            position.push_back(
                static_cast<float>(tri[i + static_cast<size_t>(k)][static_cast<size_t>(c)]));
            normal.push_back(static_cast<float>(n[static_cast<size_t>(c)]));
          }
      }
      if (position.empty()) continue;
      const int pa = w.floats(position, 3, true, 34962), na = w.floats(normal, 3, false, 34962);
      const int material = s.role == ViewShape::Role::joint ? 0 : s.inertia_box ? solid + 1 : solid;
      primitives += std::string(primitives.empty() ? "" : ",") +
                    "{\"attributes\":{\"POSITION\":" + std::to_string(pa) +
                    ",\"NORMAL\":" + std::to_string(na) +
                    "},\"material\":" + std::to_string(material) + ",\"mode\":4}";
    }
    if (!lines.empty())
      primitives += std::string(primitives.empty() ? "" : ",") + "{\"attributes\":{\"POSITION\":" +
                    std::to_string(w.floats(lines, 3, true, 34962)) +
                    "},\"material\":1,\"mode\":1}";
    const int node = node_count++;
    children += std::string(children.empty() ? "" : ",") + std::to_string(node);
    std::string n = "{\"name\":" + json_string(body.name);
    if (!primitives.empty()) {
      const int mesh = mesh_count++;
      meshes += std::string(mesh ? "," : "") + "{\"name\":" + json_string(body.name) +
                ",\"primitives\":[" + primitives + "]}";
      n += ",\"mesh\":" + std::to_string(mesh);
    }
    char b3[160];
    const Vec3& p = body.position.front();
    const Quat& q = body.orientation.front();
    std::snprintf(b3, sizeof b3,
                  ",\"translation\":[%.9g,%.9g,%.9g],\"rotation\":[%.9g,%.9g,%.9g,%.9g]}", p[0],
                  p[1], p[2], q[1], q[2], q[3], q[0]);
    nodes += "," + n + b3;
    if (times_accessor >= 0 && body.position.size() == scene.times.size()) {
      std::vector<float> tr, ro;
      Quat last = body.orientation[keys.front()];
      for (const size_t k : keys) {
        for (const double x : body.position[k]) tr.push_back(static_cast<float>(x));
        Quat r = body.orientation[k];
        // The same rotation on the previous key's side, for the shortest interpolation.
        if (r[0] * last[0] + r[1] * last[1] + r[2] * last[2] + r[3] * last[3] < 0)
          for (double& c : r) c = -c;
        last = r;
        for (const int c : {1, 2, 3, 0})
          ro.push_back(static_cast<float>(r[static_cast<size_t>(c)]));
      }
      const int sampler = sampler_count;
      sampler_count += 2;
      samplers +=
          std::string(sampler ? "," : "") + "{\"input\":" + std::to_string(times_accessor) +
          ",\"interpolation\":\"LINEAR\",\"output\":" + std::to_string(w.floats(tr, 3, false, 0)) +
          "},{\"input\":" + std::to_string(times_accessor) +
          ",\"interpolation\":\"LINEAR\",\"output\":" + std::to_string(w.floats(ro, 4, false, 0)) +
          "}";
      channels += std::string(channels.empty() ? "" : ",") +
                  "{\"sampler\":" + std::to_string(sampler) +
                  ",\"target\":{\"node\":" + std::to_string(node) +
                  ",\"path\":\"translation\"}},{\"sampler\":" + std::to_string(sampler + 1) +
                  ",\"target\":{\"node\":" + std::to_string(node) + ",\"path\":\"rotation\"}}";
    }
  }
  for (size_t i = 0; i < material_list.size(); ++i) materials += (i ? "," : "") + material_list[i];
  // The root turns the model's up into glTF's +Y: the rotation taking `up` to (0, 1, 0).
  const Vec3 up = mul(1 / norm(scene.up), scene.up), y{0, 1, 0};
  Vec3 axis = cross(up, y);
  const double c = up[1];
  Quat root{1, 0, 0, 0};
  if (norm(axis) > 1e-12) {
    axis = mul(1 / norm(axis), axis);
    const double half = std::acos(std::clamp(c, -1.0, 1.0)) / 2;
    root = {std::cos(half), std::sin(half) * axis[0], std::sin(half) * axis[1],
            std::sin(half) * axis[2]};
  } else if (c < 0) {
    root = {0, 1, 0, 0};
  }
  char rb[128];
  std::snprintf(rb, sizeof rb, "\"rotation\":[%.17g,%.17g,%.17g,%.17g]", root[1], root[2], root[3],
                root[0]);
  while (w.bin.size() % 4) w.bin += '\0';
  std::string json =
      "{\"asset\":{\"version\":\"2.0\",\"generator\":\"mechgen view\"},\"scene\":0,"
      "\"scenes\":[{\"name\":" +
      json_string(scene.title) +
      ",\"nodes\":[0]}],"
      "\"nodes\":[{\"name\":\"mechanism\"," +
      rb + ",\"children\":[" + children + "]}" + nodes + "],\"meshes\":[" + meshes +
      "],\"materials\":[" + materials +
      "],\"buffers\":[{\"byteLength\":" + std::to_string(w.bin.size()) + "}],\"bufferViews\":[" +
      w.views + "],\"accessors\":[" + w.accessors + "]";
  if (!channels.empty())
    json += ",\"animations\":[{\"name\":\"sweep\",\"channels\":[" + channels + "],\"samplers\":[" +
            samplers + "]}]";
  json += "}";
  while (json.size() % 4) json += ' ';
  auto u32 = [](std::string& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
  };
  std::string glb;
  u32(glb, 0x46546C67);  // "glTF"
  u32(glb, 2);
  u32(glb, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + w.bin.size()));
  u32(glb, static_cast<std::uint32_t>(json.size()));
  u32(glb, 0x4E4F534A);  // "JSON"
  glb += json;
  u32(glb, static_cast<std::uint32_t>(w.bin.size()));
  u32(glb, 0x004E4942);  // "BIN"
  glb += w.bin;
  return glb;
}

}  // namespace mechgen::report
