#include <gtest/gtest.h>

#include "massid/model.hpp"

TEST(Model, LoadsPuma) {
  const auto m = massid::load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  EXPECT_EQ(m.num_joints(), 3);
  EXPECT_EQ(m.num_links(), 5);
}
