// Fingerprints: a compiled-in kernel is used only for the very description it was generated from.
// Each edit of the issue (gravity off, the driver law doubled, a point moved 10 mm, a parameter's
// default changed) makes slider_crank's compiled-in kernel stale; comments and layout do not. The
// same for the spatial leg6, whose kernel comes from the spatial templates.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>
#include <string>

#include "leg6/leg6.hpp"
#include "model/fingerprint.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "model/support_model.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen {
namespace {

std::string shipped_text(const std::string& name) {
  std::ifstream in(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `text` with its one occurrence of `from` replaced by `to`.
std::string edited(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << from << " is not unique";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

Model slider_crank(const std::string& text) {
  return read_model_text(text, "models/slider_crank.yaml");
}

TEST(Fingerprint, Fnv1aOfKnownStrings) {
  // The published FNV-1a 64 test vectors.
  Fnv1a64 empty;
  EXPECT_EQ(empty.value(), 0xcbf29ce484222325ULL);
  Fnv1a64 a;
  a.add("a");
  EXPECT_EQ(a.value(), 0xaf63dc4c8601ec8cULL);
  Fnv1a64 foobar;
  foobar.add("foobar");
  EXPECT_EQ(foobar.value(), 0x85944171f73967e8ULL);
  EXPECT_EQ(hex64(0xaf63dc4c8601ec8cULL), "af63dc4c8601ec8c");
}

TEST(Fingerprint, CanonicalFormKeepsStructureAndDropsLayout) {
  EXPECT_EQ(canonical_yaml(YAML::Load("{a: [1, x], b: {c: 2}}")),
            canonical_yaml(YAML::Load("# note\na:\n  - 1\n  - x   # comment\nb:\n  c: 2\n")));
  // A scalar cannot fake structure, and order is kept (parameter order is the kernels' order).
  EXPECT_NE(canonical_yaml(YAML::Load("[ab, c]")), canonical_yaml(YAML::Load("[a, bc]")));
  EXPECT_NE(canonical_yaml(YAML::Load("{a: 1, b: 2}")), canonical_yaml(YAML::Load("{b: 2, a: 1}")));
}

TEST(Fingerprint, EveryShippedCompiledInKernelIsCurrent) {
  int spatial = 0;
  for (const std::string& name : compiled_kernel_models()) {
    if (const auto support = split_support_model_name(name)) {
      // A single-support kernel: the description welded on the body its name says.
      const SpatialModel model =
          weld_support(read_spatial_model_text(shipped_text(support->first),
                                               "models/" + support->first + ".yaml"),
                       support->second);
      const CompiledKernel* kernel = ondemand::current_compiled_kernel(model);
      ASSERT_NE(kernel, nullptr) << name;
      EXPECT_EQ(kernel, find_compiled_kernel(name));
      continue;
    }
    const std::string path = std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml";
    if (is_spatial_description(path)) {
      ++spatial;
      const SpatialModel model =
          read_spatial_model_text(shipped_text(name), "models/" + name + ".yaml");
      const CompiledKernel* kernel = ondemand::current_compiled_kernel(model);
      ASSERT_NE(kernel, nullptr) << name;
      EXPECT_EQ(kernel, find_compiled_kernel(name));
      EXPECT_EQ(kernel->fingerprint, ondemand::expected_fingerprint(model)) << name;
      // A spatial kernel is never taken for the planar reading of the same description.
      EXPECT_NE(kernel->fingerprint, ondemand::expected_fingerprint(model.common)) << name;
      continue;
    }
    const Model model = read_model_text(shipped_text(name), "models/" + name + ".yaml");
    const CompiledKernel* kernel = ondemand::current_compiled_kernel(model);
    ASSERT_NE(kernel, nullptr) << name;
    EXPECT_EQ(kernel, find_compiled_kernel(name));
    EXPECT_EQ(kernel->fingerprint, ondemand::expected_fingerprint(model)) << name;
  }
  EXPECT_GE(spatial, 1);  // leg6 at least
  // The header's constant is the registry's.
  EXPECT_EQ(gen::leg6::fingerprint, find_compiled_kernel("leg6")->fingerprint);
}

TEST(Fingerprint, CommentsAndLayoutKeepTheKernel) {
  const std::string text = shipped_text("slider_crank");
  const Model original = slider_crank(text);
  const Model commented =
      slider_crank("# edited by hand\n" +
                   edited(edited(text, "# a full crank turn", "# one turn, commented anew"),
                          "gravity: [0, -9.81]", "gravity:   [ 0,   -9.81 ]  # g"));
  EXPECT_EQ(commented.description_hash, original.description_hash);
  EXPECT_NE(ondemand::current_compiled_kernel(commented), nullptr);
}

TEST(Fingerprint, EachEditMakesTheCompiledInKernelStale) {
  const std::string text = shipped_text("slider_crank");
  const Model original = slider_crank(text);
  ASSERT_NE(ondemand::current_compiled_kernel(original), nullptr);
  const struct {
    const char* what;
    std::string text;
  } edits[] = {
      {"gravity set to zero", edited(text, "gravity: [0, -9.81]", "gravity: [0, 0]")},
      {"driver law doubled",
       edited(text, "kind: angle, value: w*t}", "kind: angle, value: 2*w*t}")},
      {"point moved 10 mm", edited(text, "P: [r, 0]}", "P: [r + 0.01, 0]}")},
      {"parameter default changed", edited(text, "r: {value: 0.05,", "r: {value: 0.06,")},
  };
  for (const auto& edit : edits) {
    const Model model = slider_crank(edit.text);
    EXPECT_NE(model.description_hash, original.description_hash) << edit.what;
    EXPECT_NE(ondemand::expected_fingerprint(model),
              find_compiled_kernel("slider_crank")->fingerprint)
        << edit.what;
    EXPECT_EQ(ondemand::current_compiled_kernel(model), nullptr) << edit.what;
  }
}

SpatialModel leg6(const std::string& text) {
  return read_spatial_model_text(text, "models/leg6.yaml");
}

TEST(Fingerprint, SpatialCommentsAndLayoutKeepTheKernel) {
  const std::string text = shipped_text("leg6");
  const SpatialModel original = leg6(text);
  ASSERT_NE(original.common.description_hash, 0u);
  const SpatialModel commented =
      leg6("# edited by hand\n" +
           edited(text, "gravity: [0, 0, -9.81]", "gravity:  [ 0, 0,  -9.81 ]   # down"));
  EXPECT_EQ(commented.common.description_hash, original.common.description_hash);
  EXPECT_EQ(ondemand::current_compiled_kernel(commented), find_compiled_kernel("leg6"));
}

TEST(Fingerprint, EachEditMakesTheSpatialCompiledInKernelStale) {
  const std::string text = shipped_text("leg6");
  const SpatialModel original = leg6(text);
  ASSERT_NE(ondemand::current_compiled_kernel(original), nullptr);
  const struct {
    const char* what;
    std::string text;
  } edits[] = {
      {"gravity set to zero", edited(text, "gravity: [0, 0, -9.81]", "gravity: [0, 0, 0]")},
      {"driver law doubled", edited(text, "value: 0.1*sin(w*t)", "value: 0.2*sin(w*t)")},
      {"point moved 10 mm", edited(text, "toe: [0.06, 0,", "toe: [0.07, 0,")},
      {"parameter default changed", edited(text, "l1: {value: 0.075,", "l1: {value: 0.085,")},
  };
  for (const auto& edit : edits) {
    const SpatialModel model = leg6(edit.text);
    EXPECT_NE(model.common.description_hash, original.common.description_hash) << edit.what;
    EXPECT_NE(ondemand::expected_fingerprint(model), find_compiled_kernel("leg6")->fingerprint)
        << edit.what;
    EXPECT_EQ(ondemand::current_compiled_kernel(model), nullptr) << edit.what;
  }
}

}  // namespace
}  // namespace mechgen
