// The parametric driver the driver-as-deformer tests share (issue 21): fitted to the sheet in front of
// the demo character's chest (patch_fixtures.h chest_sheet), one control point pushed out by `push`.
#pragma once

#include <memory>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "core/deform/patch_fit.h"
#include "core/document/document.h"
#include "tests/patch_fixtures.h"

namespace cagewrap::test {

inline std::shared_ptr<PatchDriver> chest_driver(double push) {
  const PolyMesh sheet = chest_sheet();
  std::vector<uint32_t> faces(sheet.num_faces());
  std::iota(faces.begin(), faces.end(), 0u);
  auto grid = fit_patch_to_faces(sheet, sheet.positions, faces);
  EXPECT_TRUE(grid.ok()) << grid.error().message;
  auto d = std::make_shared<PatchDriver>();
  d->rest.grids = {*grid};
  d->posed = d->rest;
  auto points = d->posed.control_points();
  points[14] += glm::dvec3(0.0, 0.0, push);  // pushed out of the chest
  d->posed.set_control_points(points);
  d->density = 2;
  d->drive_skin = true;
  return d;
}

}  // namespace cagewrap::test
