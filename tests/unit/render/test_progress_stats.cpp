#include <gtest/gtest.h>

#include <vector>

#include "visfield/core/parallel.hpp"
#include "visfield/render/progress.hpp"
#include "visfield/render/render_stats.hpp"
#include "visfield/render/tiles.hpp"

namespace vf {
namespace {

TEST(ProgressBar, DisabledPrintsNothing) {
  testing::internal::CaptureStderr();
  {
    ProgressBar bar("render", 10, false, 0.0);
    for (int i = 0; i < 10; ++i) bar.tick();
    bar.finish();
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(ProgressBar, ShortJobsPrintNothing) {
  testing::internal::CaptureStderr();
  {
    ProgressBar bar("render", 10, true, 1e6);
    bar.tick(10);
  }  // the destructor finishes
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(ProgressBar, LongJobsDrawTheBarAndEndAtHundredPercent) {
  testing::internal::CaptureStderr();
  {
    ProgressBar bar("render", 4, true, 0.0);
    bar.tick(2);
    bar.finish();
    bar.finish();  // a second finish prints nothing more
  }
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_NE(out.find("render ["), std::string::npos) << out;
  EXPECT_NE(out.find(" 50%"), std::string::npos) << out;
  EXPECT_NE(out.find("100%\n"), std::string::npos) << out;
  EXPECT_EQ(out.find('\n'), out.size() - 1) << out;
}

RenderStats stats_of(int width, int height, RayCounts counts, double seconds) {
  return RenderStats{width, height, counts, counts.total(), seconds};
}

TEST(RenderStats, SummaryShowsResolutionRaysByKindTimeAndRate) {
  EXPECT_EQ(stats_of(512, 512, {262'144, 0, 0, 16'537'856}, 1.23).summary(),
            "512x512, 16.8M rays (camera 262.1k, shadow 0, reflection 0, AO 16.5M), 1.23 s, 13.7 Mrays/s");
  EXPECT_EQ(stats_of(4, 3, {12, 900, 38, 0}, 0.0).summary(),
            "4x3, 950 rays (camera 12, shadow 900, reflection 38, AO 0), 0.00 s, 0.0 Mrays/s");
  EXPECT_EQ(stats_of(64, 64, {4096, 8249, 0, 0}, 0.5).summary(),
            "64x64, 12.3k rays (camera 4.1k, shadow 8.2k, reflection 0, AO 0), 0.50 s, 0.0 Mrays/s");
  EXPECT_DOUBLE_EQ(stats_of(1, 1, {3'000'000, 0, 0, 0}, 2.0).mrays_per_s(), 1.5);
}

TEST(ForEachTile, VisitsEveryPixelOnceAndSumsTheRays) {
  for (int threads : {1, 2}) {
    const ThreadLimit limit(threads);
    const int width = 37, height = 23;
    std::vector<int> visits(width * height, 0);
    RenderStats stats;
    for_each_tile(ImageTile{0, 0, width, height}, 8, "test", false, [&](const ImageTile& tile) -> RayCounts {
      EXPECT_LE(tile.x1 - tile.x0, 8);
      EXPECT_LE(tile.y1 - tile.y0, 8);
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) ++visits[y * width + x];
      const auto pixels = static_cast<std::uint64_t>((tile.x1 - tile.x0) * (tile.y1 - tile.y0));
      return RayCounts{pixels, 2 * pixels, 0, 5};
    }, &stats);
    for (int v : visits) EXPECT_EQ(v, 1);
    EXPECT_EQ(stats.rays, 3u * width * height + 5u * 15u);  // 5 x 3 tiles
    EXPECT_EQ(stats.by_kind.camera, 1u * width * height);
    EXPECT_EQ(stats.by_kind.shadow, 2u * width * height);
    EXPECT_EQ(stats.by_kind.ao, 5u * 15u);
    EXPECT_EQ(stats.width, width);
    EXPECT_EQ(stats.height, height);
  }
}

}  // namespace
}  // namespace vf
