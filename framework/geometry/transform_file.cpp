#include "framework/geometry/transform_file.h"

#include "framework/error.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace arcs {
namespace {

std::string Num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// The numbers after "key": in our own sidecar format (not a general JSON parser).
std::vector<double> NumbersAfter(const std::string& text, const std::string& key, const std::string& path, size_t count) {
  const size_t k = text.find("\"" + key + "\"");
  if (k == std::string::npos) throw InputError(path, 0, "transform sidecar has no \"" + key + "\"");
  std::vector<double> v;
  const char* p = text.c_str() + k + key.size() + 2;
  while (v.size() < count && *p) {
    if ((*p >= '0' && *p <= '9') || *p == '-' || *p == '+' || *p == '.') {
      char* end = nullptr;
      v.push_back(std::strtod(p, &end));
      p = end;
    } else {
      ++p;
    }
  }
  if (v.size() != count) throw InputError(path, 0, "transform sidecar: \"" + key + "\" needs " + std::to_string(count) + " numbers");
  return v;
}

}  // namespace

void WriteTransformSidecar(const std::string& output, const Similarity& t, const std::string& note) {
  const std::string path = output + ".transform.json";
  std::string j = "{\n  \"maps\": \"input frame -> the frame of " + std::filesystem::path(output).filename().string() +
                  ": y = scale * rotation * (x + translation)\",\n  \"scale\": " + Num(t.scale) +
                  ",\n  \"translation\": [" + Num(t.translation.x()) + ", " + Num(t.translation.y()) + ", " +
                  Num(t.translation.z()) + "],\n  \"rotation\": [";
  for (int r = 0; r < 3; ++r)
    j += std::string(r ? ", " : "") + "[" + Num(t.rotation(r, 0)) + ", " + Num(t.rotation(r, 1)) + ", " +
         Num(t.rotation(r, 2)) + "]";
  j += "],\n  \"note\": \"" + note + "\"\n}\n";
  std::ofstream f(path, std::ios::binary);
  f << j;
  if (!f) throw Error("cannot write '" + path + "'");
}

bool ReadTransformSidecar(const std::string& output, Similarity* t) {
  const std::string path = output + ".transform.json";
  std::ifstream f(path, std::ios::binary);
  if (!f) return false;
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  t->scale = NumbersAfter(text, "scale", path, 1)[0];
  const auto tr = NumbersAfter(text, "translation", path, 3);
  const auto r = NumbersAfter(text, "rotation", path, 9);
  t->translation = Vec3(tr[0], tr[1], tr[2]);
  for (int i = 0; i < 9; ++i) t->rotation(i / 3, i % 3) = r[i];
  if (!(t->scale > 0)) throw InputError(path, 0, "transform sidecar: scale must be > 0");
  return true;
}

}  // namespace arcs
