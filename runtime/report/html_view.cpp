#include "report/html_view.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mechgen::report {

extern const char* const kViewPageTemplate;  // view_page/view.html, embedded (view_page.cpp)

namespace {

void number(std::string& out, double v) {
  if (!std::isfinite(v)) throw std::runtime_error("view: a value is not finite");
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.append(buffer, result.ptr);
}

void string_value(std::string& out, const std::string& s) {
  out += '"';
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '"' || c == '\\')
      out += '\\', out += c;
    else if (c == '<')
      out += "\\u003c";  // never "</script>" inside the page's JSON
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x",
                    static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buffer;
    } else
      out += c;
  }
  out += '"';
}

template <size_t N>
void array(std::string& out, const std::array<double, N>& a) {
  out += '[';
  for (size_t i = 0; i < N; ++i) {
    if (i) out += ',';
    number(out, a[i]);
  }
  out += ']';
}

template <class T, class F>
void list(std::string& out, const std::vector<T>& items, F each) {
  out += '[';
  for (size_t i = 0; i < items.size(); ++i) {
    if (i) out += ',';
    each(items[i]);
  }
  out += ']';
}

const char* kind_name(ViewShape::Kind k) {
  switch (k) {
    case ViewShape::Kind::cylinder:
      return "cylinder";
    case ViewShape::Kind::box:
      return "box";
    case ViewShape::Kind::plate:
      return "plate";
    case ViewShape::Kind::sphere:
      return "sphere";
    case ViewShape::Kind::line:
      return "line";
  }
  return "line";
}

const char* role_name(ViewShape::Role r) {
  return r == ViewShape::Role::joint ? "joint" : r == ViewShape::Role::ground ? "ground" : "link";
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error(path +
                             ": cannot read three.js (install Debian's libjs-three, "
                             "scripts/deps.sh, or set MECHGEN_THREE_DIR)");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  if (s.find("</script") != std::string::npos)
    throw std::runtime_error(path + ": contains '</script', cannot be inlined");
  return s;
}

}  // namespace

std::string scene_json(const ViewScene& scene) {
  std::string o = "{\"title\":";
  string_value(o, scene.title);
  o += ",\"dimension\":";
  string_value(o, scene.dimension);
  o += ",\"up\":";
  array(o, scene.up);
  o += ",\"size\":";
  number(o, scene.size);
  o += ",\"times\":";
  list(o, scene.times, [&](double t) { number(o, t); });
  o += ",\n\"bodies\":";
  list(o, scene.bodies, [&](const ViewBody& b) {
    o += "\n{\"name\":";
    string_value(o, b.name);
    o += ",\"ground\":";
    o += b.ground ? "true" : "false";
    o += ",\"shapes\":";
    list(o, b.shapes, [&](const ViewShape& s) {
      o += "{\"kind\":\"";
      o += kind_name(s.kind);
      o += "\",\"role\":\"";
      o += role_name(s.role);
      o += '"';
      switch (s.kind) {
        case ViewShape::Kind::cylinder:
          o += ",\"a\":", array(o, s.a), o += ",\"b\":", array(o, s.b);
          o += ",\"radius\":", number(o, s.radius);
          break;
        case ViewShape::Kind::box:
          o += ",\"center\":", array(o, s.center), o += ",\"size\":", array(o, s.size);
          o += ",\"rotation\":", array(o, s.rotation);
          if (s.inertia_box) o += ",\"inertia_box\":true";
          break;
        case ViewShape::Kind::sphere:
          o += ",\"center\":", array(o, s.center), o += ",\"radius\":", number(o, s.radius);
          break;
        case ViewShape::Kind::plate:
          o += ",\"thickness\":", number(o, s.thickness);
          [[fallthrough]];
        case ViewShape::Kind::line:
          o += ",\"outline\":";
          list(o, s.outline, [&](const Vec3& p) { array(o, p); });
          break;
      }
      o += '}';
    });
    o += ",\n\"position\":";
    list(o, b.position, [&](const Vec3& p) { array(o, p); });
    o += ",\n\"orientation\":";
    list(o, b.orientation, [&](const Quat& q) { array(o, q); });
    o += '}';
  });
  auto labels = [&](const std::vector<ViewLabel>& items) {
    list(o, items, [&](const ViewLabel& l) {
      o += "{\"name\":";
      string_value(o, l.name);
      o += ",\"body\":" + std::to_string(l.body) + ",\"local\":";
      array(o, l.local);
      o += '}';
    });
  };
  o += ",\n\"points\":";
  labels(scene.points);
  o += ",\n\"joints\":";
  labels(scene.joints);
  o += ",\n\"traces\":";
  list(o, scene.traces, [&](const std::pair<std::string, std::vector<Vec3>>& t) {
    o += "{\"name\":";
    string_value(o, t.first);
    o += ",\"path\":";
    list(o, t.second, [&](const Vec3& p) { array(o, p); });
    o += '}';
  });
  o += ",\n\"plot\":";
  list(o, scene.plot, [&](const ViewSeries& s) {
    o += "{\"name\":";
    string_value(o, s.name);
    o += ",\"values\":";
    list(o, s.values, [&](double v) { number(o, v); });
    o += '}';
  });
  o += ",\"plot_note\":";
  string_value(o, scene.plot_note);
  return o + "}";
}

std::string three_js_dir() {
  const char* dir = std::getenv("MECHGEN_THREE_DIR");
  return dir && *dir ? dir : "/usr/share/javascript/three";
}

std::string render_html_view(const ViewScene& scene) {
  const std::string dir = three_js_dir();
  const std::string three = read_text(dir + "/three.min.js");
  const std::string orbit = read_text(dir + "/examples/js/controls/OrbitControls.js");
  std::string title;
  for (const char c : scene.title)
    title += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
  // Markers are replaced in the template only, never inside what replaces them.
  const std::string json = scene_json(scene);
  const std::string page = kViewPageTemplate;
  std::string out;
  size_t at = 0;
  while (true) {
    const size_t open = page.find('@', at);
    const size_t close = open == std::string::npos ? open : page.find('@', open + 1);
    if (close == std::string::npos) break;
    const std::string key = page.substr(open + 1, close - open - 1);
    const std::string* fill = key == "TITLE"               ? &title
                              : key == "THREE_JS"          ? &three
                              : key == "ORBIT_CONTROLS_JS" ? &orbit
                              : key == "SCENE_JSON"        ? &json
                                                           : nullptr;
    if (!fill) {  // an '@' of the page itself
      out.append(page, at, open + 1 - at);
      at = open + 1;
      continue;
    }
    out.append(page, at, open - at);
    out += *fill;
    at = close + 1;
  }
  out.append(page, at, std::string::npos);
  return out;
}

}  // namespace mechgen::report
