// Scene parsing of the `continuum` block: every scene of the repository reads,
// every key is checked, and errors name the dotted key.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "scene/continuum_json.hpp"

using namespace xfdem;
using scene::Json;

namespace {

Json v2() {
  return Json::parse(R"({
    "type": "bar", "method": "xfem", "length": 30, "youngs_modulus": 3e7, "area": 0.4, "density": 2000,
    "elements": 30, "base": "fixed",
    "interface": { "position": 14.5, "stiffness": 1.2e9, "behaviour": "tied" },
    "newmark": { "beta": 0.4, "gamma": 0.6 },
    "tip_load": { "shape": "half_sine", "amplitude": -1e4, "duration": 0.25 } })");
}

BarDesc parse(const Json& j, double dt = 1e-3) {
  scene::ObjectReader r(j, "continuum");
  return scene::parse_continuum(r, dt);
}

std::string error_of(const Json& j, double dt = 1e-3) {
  try {
    parse(j, dt);
  } catch (const scene::SceneError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const Json& j, const std::string& key) {
  const std::string message = error_of(j);
  EXPECT_NE(message.find("'" + key + "'"), std::string::npos) << "expected an error naming " << key << ", got: " << message;
}

}  // namespace

TEST(ContinuumJson, ReadsTheV2Rod) {
  const BarDesc d = parse(v2());
  EXPECT_EQ(d.method, BarDesc::Method::xfem);
  EXPECT_EQ(d.length, 30.0);
  EXPECT_EQ(d.elements, 30);
  ASSERT_TRUE(d.interface.has_value());
  EXPECT_EQ(d.interface->position, 14.5);
  EXPECT_EQ(d.interface->stiffness, 1.2e9);
  EXPECT_EQ(d.beta, 0.4);
  EXPECT_EQ(d.gamma, 0.6);
  EXPECT_EQ(d.tip_load, BarDesc::TipLoad::half_sine);
  EXPECT_EQ(d.tip_amplitude, -1e4);
  EXPECT_EQ(d.tip_duration, 0.25);
  EXPECT_EQ(d.dt, 1e-3);
  BarModel m;
  BarState s;
  BarWorkspace w;
  EXPECT_TRUE(build_bar(d, m, s, w).ok());
}

TEST(ContinuumJson, ReadsEverySceneOfTheRepository) {
  for (const char* name : {"v2_fem", "v2_xfem", "case1_fem", "case1_xfem", "case2_fem", "case2_xfem"}) {
    std::ifstream in(std::string(XFDEM_SOURCE_DIR) + "/scenes/" + name + ".json");
    ASSERT_TRUE(in.good()) << name;
    const Json scene = Json::parse(in);
    const BarDesc d = parse(scene.at("continuum"), scene.at("time").at("dt").get<double>());
    BarModel m;
    BarState s;
    BarWorkspace w;
    EXPECT_TRUE(build_bar(d, m, s, w).ok()) << name;
  }
}

TEST(ContinuumJson, OptionalBlocks) {
  Json j = v2();
  j.erase("interface");
  j.erase("tip_load");
  const BarDesc d = parse(j);
  EXPECT_FALSE(d.interface.has_value());
  EXPECT_EQ(d.tip_load, BarDesc::TipLoad::none);
  j["base"] = "absorbing";
  j["base_stiffness"] = 1e6;
  EXPECT_EQ(parse(j).base_stiffness, 1e6);
  j["tip_load"] = Json::parse(R"({"shape": "step", "amplitude": 5})");
  EXPECT_EQ(parse(j).tip_load, BarDesc::TipLoad::step);
}

TEST(ContinuumJson, RejectsBadValuesNamingTheKey) {
  auto with = [](const char* pointer, Json value) {
    Json j = v2();
    j[Json::json_pointer(pointer)] = std::move(value);
    return j;
  };
  expect_error(with("/type", "beam"), "continuum.type");
  expect_error(with("/method", "xfm"), "continuum.method");
  expect_error(with("/length", -1), "continuum.length");
  expect_error(with("/youngs_modulus", 0), "continuum.youngs_modulus");
  expect_error(with("/area", "big"), "continuum.area");
  expect_error(with("/density", 0), "continuum.density");
  expect_error(with("/elements", 2.5), "continuum.elements");
  expect_error(with("/elements", 0), "continuum.elements");
  expect_error(with("/base", "soft"), "continuum.base");
  expect_error(with("/base_stiffness", 1e6), "continuum.base_stiffness");  // fixed base
  expect_error(with("/interface/position", 31), "continuum.interface.position");
  expect_error(with("/interface/position", 30), "continuum.interface.position");
  expect_error(with("/interface/stiffness", -5), "continuum.interface.stiffness");
  expect_error(with("/interface/behaviour", "glued"), "continuum.interface.behaviour");
  expect_error(with("/newmark/gamma", 0.4), "continuum.newmark.gamma");
  expect_error(with("/newmark/beta", 0.25), "continuum.newmark.beta");  // γ = 0.6 needs β ≥ 0.3025
  expect_error(with("/tip_load/shape", "square"), "continuum.tip_load.shape");
  expect_error(with("/tip_load/duration", 0), "continuum.tip_load.duration");
  expect_error(with("/tip_load/shape", "step"), "continuum.tip_load.duration");  // step has no duration
  expect_error(with("/tip_load/amplitude", "loud"), "continuum.tip_load.amplitude");
  Json missing = v2();
  missing.erase("newmark");
  expect_error(missing, "continuum.newmark");
  EXPECT_NE(error_of(v2(), 0.0).find("'time.dt'"), std::string::npos);
}

TEST(ContinuumJson, RejectsUnknownKeysAtEveryLevel) {
  auto with = [](const char* pointer) {
    Json j = v2();
    j[Json::json_pointer(pointer)] = 1;
    return j;
  };
  expect_error(with("/lenght"), "continuum.lenght");
  expect_error(with("/interface/postion"), "continuum.interface.postion");
  expect_error(with("/newmark/alpha"), "continuum.newmark.alpha");
  expect_error(with("/tip_load/period"), "continuum.tip_load.period");
}
