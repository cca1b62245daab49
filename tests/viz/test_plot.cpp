#include "vdtnav/viz/plot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav::viz {
namespace {

std::string tmp_path(const std::string& name) {
  std::filesystem::create_directories(VDTNAV_TEST_TMP);
  return std::string(VDTNAV_TEST_TMP) + "/" + name;
}

Rgb pixel_at(const RgbImage& img, Point p) {
  return img.at(static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)));
}

TEST(NiceTicks, OneTwoFiveStepsCoverTheRangeWithThreeToTenTicks) {
  const std::vector<std::pair<double, double>> ranges{
      {0, 1},        {0, 0.9},       {-3.7, 12.2}, {1e-5, 3e-4},    {0.0012, 0.0013},
      {-1e6, 5e6},   {100, 101},     {-0.5, 0.5},  {3, 1003},       {0, 7},
      {-2e-9, 1e-9}, {42.17, 42.19}, {-180, 180},  {0.999, 1.0001}, {-71.3, -70.1}};
  for (const auto& [lo, hi] : ranges) {
    const std::vector<double> t = nice_ticks(lo, hi);
    ASSERT_GE(t.size(), 3u) << lo << " .. " << hi;
    ASSERT_LE(t.size(), 10u) << lo << " .. " << hi;
    const double step = t[1] - t[0];
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 ||
                std::abs(mantissa - 5) < 1e-6)
        << "step " << step << " for " << lo << " .. " << hi;
    for (std::size_t i = 0; i < t.size(); ++i) {
      EXPECT_NEAR(t[i] / step, std::round(t[i] / step), 1e-6);  // multiples of the step
      if (i > 0) {
        EXPECT_NEAR(t[i] - t[i - 1], step, 1e-9 * step);
      }
      EXPECT_GE(t[i], lo - 1e-9 * step);
      EXPECT_LE(t[i], hi + 1e-9 * step);
    }
    EXPECT_LT(t.front() - lo, step);  // no room for another tick at either end
    EXPECT_LT(hi - t.back(), step);
  }
  EXPECT_EQ(nice_ticks(0.0, 1.0, 6), (std::vector<double>{0.0, 0.2, 0.4, 0.6, 0.8, 1.0}));
  EXPECT_TRUE(nice_ticks(0.0, std::nan(""), 6).empty());
}

TEST(FormatTick, CompactLabels) {
  EXPECT_EQ(format_tick(0.0, 0.005), "0");
  EXPECT_EQ(format_tick(0.005, 0.005), "0.005");
  EXPECT_EQ(format_tick(0.01, 0.005), "0.010");
  EXPECT_EQ(format_tick(-2.5, 0.5), "-2.5");
  EXPECT_EQ(format_tick(1200, 200), "1200");
  EXPECT_EQ(format_tick(3.0, 1.0), "3");
  EXPECT_EQ(format_tick(1e-4, 1e-4), "1e-4");
  EXPECT_EQ(format_tick(1.5e-4, 5e-5), "1.5e-4");
  EXPECT_EQ(format_tick(-2e-4, 1e-4), "-2e-4");
  EXPECT_EQ(format_tick(2.5e6, 5e5), "2.5e6");
  EXPECT_EQ(format_tick(5e5, 5e5), "5e5");  // same style as 2.5e6 on that axis
  EXPECT_EQ(format_tick(1.5e6, 1e4), "1500000");
  EXPECT_EQ(format_tick(1e-12, 0.1), "0");  // rounding noise around zero
}

TEST(Axes, PixelMappingInvertsAndPutsTheLimitsOnTheFrame) {
  Figure fig(600, 400);
  Axes& ax = fig.axes();
  ax.xlim(-2.0, 3.0).ylim(10.0, 20.0).title("t").xlabel("x").ylabel("y");
  (void)fig.render();
  const PixelRect a = ax.plot_area();
  ASSERT_GT(a.width, 100);
  ASSERT_GT(a.height, 100);
  EXPECT_LT(a.x + a.width, 600);
  EXPECT_LT(a.y + a.height, 400);
  const Point bl = ax.to_pixel(-2.0, 10.0), tr = ax.to_pixel(3.0, 20.0);
  EXPECT_DOUBLE_EQ(bl.x, a.x);
  EXPECT_DOUBLE_EQ(bl.y, a.y + a.height);  // y up: the lower limit is at the bottom
  EXPECT_DOUBLE_EQ(tr.x, a.x + a.width);
  EXPECT_DOUBLE_EQ(tr.y, a.y);
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{0.3, 11.1}, {-1.9, 19.5}}) {
    const Point d = ax.to_data(ax.to_pixel(x, y));
    EXPECT_NEAR(d.x, x, 1e-12);
    EXPECT_NEAR(d.y, y, 1e-12);
  }
  const Point p{a.x + 17.25, a.y + 33.5};
  const Point q = ax.to_pixel(ax.to_data(p).x, ax.to_data(p).y);
  EXPECT_NEAR(q.x, p.x, 1e-9);
  EXPECT_NEAR(q.y, p.y, 1e-9);
}

TEST(Axes, SeriesLandWhereTheMappingSays) {
  Figure fig(500, 400);
  Axes& ax = fig.axes();
  const Rgb red{220, 0, 0}, green{0, 160, 0};
  ax.xlim(0, 10).ylim(0, 5).grid(false);
  ax.scatter({2.0}, {4.0}, Style().with_color(red).with_marker(Marker::kSquare, 9));
  ax.line({1.0, 9.0}, {1.0, 1.0}, Style().with_color(green).with_width(4));
  const RgbImage img = fig.render();
  EXPECT_EQ(pixel_at(img, ax.to_pixel(2.0, 4.0)), red);
  EXPECT_EQ(pixel_at(img, ax.to_pixel(5.0, 1.0)), green);
  EXPECT_EQ(pixel_at(img, ax.to_pixel(5.0, 3.0)), kWhite);
  EXPECT_EQ(pixel_at(img, ax.to_pixel(7.0, 4.0)), kWhite);
}

TEST(Axes, AutoLimitsAddFivePercent) {
  Figure fig(600, 400);
  Axes& ax = fig.axes();
  ax.line({0.0, 5.0, 10.0}, {-1.0, std::nan(""), 1.0});
  (void)fig.render();
  EXPECT_DOUBLE_EQ(ax.x_range().first, -0.5);
  EXPECT_DOUBLE_EQ(ax.x_range().second, 10.5);
  EXPECT_DOUBLE_EQ(ax.y_range().first, -1.1);
  EXPECT_DOUBLE_EQ(ax.y_range().second, 1.1);
}

TEST(Axes, EqualAspectGivesSameUnitsPerPixel) {
  Figure fig(800, 600);
  Axes& ax = fig.axes();
  ax.line({0.0, 10.0}, {0.0, 2.0}).equal_aspect();
  (void)fig.render();
  const PixelRect a = ax.plot_area();
  const auto [x0, x1] = ax.x_range();
  const auto [y0, y1] = ax.y_range();
  EXPECT_NEAR((x1 - x0) / a.width, (y1 - y0) / a.height, 1e-12);
  EXPECT_LE(x0, -0.5 + 1e-9);  // the data with their margin stay in view
  EXPECT_GE(x1, 10.5 - 1e-9);
  EXPECT_LE(y0, -0.1 + 1e-9);
  EXPECT_GE(y1, 2.1 - 1e-9);
  EXPECT_LT(a.height, a.width / 3);  // the box shrank instead of stretching the data
}

TEST(Axes, BackgroundImageIsPlacedInDataCoordinates) {
  RgbImage src(2, 2);
  const Rgb tl{255, 0, 0}, tr{0, 255, 0}, bl{0, 0, 255}, br{90, 60, 30};
  src.set(0, 0, tl);
  src.set(1, 0, tr);
  src.set(0, 1, bl);
  src.set(1, 1, br);
  Figure fig(600, 500);
  Axes& ax = fig.axes();
  ax.image(src, 0.0, 4.0, 0.0, 2.0).equal_aspect();
  const RgbImage img = fig.render();
  EXPECT_DOUBLE_EQ(ax.x_range().first, 0.0);  // images are shown exactly, no margin
  EXPECT_DOUBLE_EQ(ax.x_range().second, 4.0);
  EXPECT_EQ(pixel_at(img, ax.to_pixel(1.0, 1.5)), tl);  // row 0 of the image is at y_max
  EXPECT_EQ(pixel_at(img, ax.to_pixel(3.0, 1.5)), tr);
  EXPECT_EQ(pixel_at(img, ax.to_pixel(1.0, 0.5)), bl);
  EXPECT_EQ(pixel_at(img, ax.to_pixel(3.0, 0.5)), br);
}

TEST(Axes, BandTakesTheColourOfTheLineDrawnAfterIt) {
  Figure fig(500, 400);
  Axes& ax = fig.axes();
  ax.xlim(0, 10).ylim(-3, 3).grid(false);
  ax.band({0.0, 10.0}, {-2.0, -2.0}, {2.0, 2.0});
  ax.line({0.0, 10.0}, {0.0, 0.0}, Style().with_width(4));  // wide enough for a full pixel
  ax.line({0.0, 10.0}, {-2.5, -2.5}, Style().with_width(4));
  const RgbImage img = fig.render();
  const Rgb c0 = kColorCycle[0];
  EXPECT_EQ(pixel_at(img, ax.to_pixel(5.0, 0.0)), c0);
  EXPECT_EQ(pixel_at(img, ax.to_pixel(5.0, -2.5)), kColorCycle[1]);
  const Rgb band = pixel_at(img, ax.to_pixel(5.0, 1.0));
  const auto mix = [](int c) { return static_cast<int>(std::lround(255 + 0.25 * (c - 255))); };
  EXPECT_EQ(band, (Rgb{std::uint8_t(mix(c0.r)), std::uint8_t(mix(c0.g)), std::uint8_t(mix(c0.b))}));
}

TEST(Figure, TextStaysInsideTheFigureAndTheLabelsBesideThePlot) {
  for (const int scale : {1, 2, 3}) {
    Figure fig(700, 450);
    fig.font_scale(scale).title("Whole figure title");
    Axes& ax = fig.axes();
    ax.xlim(-12345.0, 98765.0).ylim(-0.0042, 0.0031).title("Axes title").xlabel("x label [m]");
    ax.ylabel("y label [m]").colorbar(Colormap::kViridis, 0.0, 250.0, "colour [units]");
    ax.line({0.0, 5e4}, {0.0, 0.002}, Style().with_label("a legend entry"));
    const RgbImage img = fig.render();
    const PixelRect a = ax.plot_area();
    // Nothing clipped: a 2-pixel border of the canvas stays white.
    for (int x = 0; x < img.width; ++x) {
      for (const int y : {0, 1, img.height - 2, img.height - 1}) {
        EXPECT_EQ(img.at(x, y), kWhite) << x << "," << y << " scale " << scale;
      }
    }
    for (int y = 0; y < img.height; ++y) {
      for (const int x : {0, 1, img.width - 2, img.width - 1}) {
        EXPECT_EQ(img.at(x, y), kWhite) << x << "," << y << " scale " << scale;
      }
    }
    // Ink left of the plot (y label and ticks), under it (x label) and above it (titles).
    const auto inked = [&img](int x0, int y0, int x1, int y1) {
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          if (img.at(x, y) != kWhite) return true;
        }
      }
      return false;
    };
    EXPECT_TRUE(inked(0, a.y, a.x - 12 * scale, a.y + a.height)) << scale;
    EXPECT_TRUE(inked(a.x, a.y + a.height + 20 * scale, a.x + a.width, img.height)) << scale;
    EXPECT_TRUE(inked(a.x, 0, a.x + a.width, a.y - 2)) << scale;
    EXPECT_TRUE(inked(a.x + a.width + 30 * scale, a.y, img.width, a.y + a.height)) << scale;
  }
}

TEST(Figure, RejectsBadArgumentsAndUnwritablePaths) {
  EXPECT_THROW(Figure(0, 10), ConfigError);
  Figure fig(300, 200, 2, 3);
  EXPECT_NO_THROW((void)fig.axes(1, 2));
  EXPECT_THROW((void)fig.axes(2, 0), ConfigError);
  EXPECT_THROW(fig.axes().xlim(1.0, 1.0), ConfigError);
  EXPECT_THROW(fig.axes().line({1.0, 2.0}, {1.0}), ConfigError);
  EXPECT_THROW(fig.save_png(tmp_path("missing_dir/fig.png")), IoError);
}

/// The demo a reader looks at: a signed distance field with a trajectory and colorbar, and an
/// error plot with its 2-sigma envelope and a legend.
TEST(Figure, DemoFigureWithHeatmapColorbarBandAndLegend) {
  // Signed distance to two walls and a round pillar in a 10 m x 6 m room, 5 cm cells.
  const GridFrame<2> frame(0.05, Eigen::Vector2d(-1.0, -0.5));
  Grid<float, 2> sdf(Eigen::Vector2i(200, 120), frame);
  for (int y = 0; y < 120; ++y) {
    for (int x = 0; x < 200; ++x) {
      const Eigen::Vector2d p = sdf.cell_center(Eigen::Vector2i(x, y));
      const double walls = std::min({p.y() + 0.5, 5.5 - p.y(), p.x() + 1.0, 9.0 - p.x()});
      const double pillar = (p - Eigen::Vector2d(4.0, 2.5)).norm() - 0.8;
      sdf(Eigen::Vector2i(x, y)) = static_cast<float>(std::min(walls, pillar));
    }
  }
  sdf(Eigen::Vector2i(10, 10)) = std::nanf("");
  const auto [lo, hi] = finite_range(sdf);
  const double m = std::max(-lo, hi);
  std::vector<double> tx, ty, t, err, sig_lo, sig_hi;
  for (int k = 0; k <= 200; ++k) {
    const double a = 2.0 * kPi * k / 200.0;
    tx.push_back(4.0 + 2.8 * std::cos(a));
    ty.push_back(2.5 + 1.8 * std::sin(a));
    t.push_back(0.1 * k);
    const double sigma = 0.02 + 0.01 * std::sin(0.05 * k) * std::sin(0.05 * k);
    err.push_back(sigma * std::sin(0.7 * k) * std::cos(0.13 * k));
    sig_lo.push_back(-2.0 * sigma);
    sig_hi.push_back(2.0 * sigma);
  }

  Figure fig(1200, 800, 1, 2);
  fig.title("vdtnav::viz demo");
  Axes& map = fig.axes(0, 0);
  map.image(heatmap(sdf, Colormap::kBlueWhiteRed, -m, m), -1.0, 9.0, -0.5, 5.5)
      .equal_aspect()
      .colorbar(Colormap::kBlueWhiteRed, -m, m, "signed distance [m]")
      .title("Signed distance field")
      .xlabel("x [m]")
      .ylabel("y [m]");
  map.line(tx, ty, Style().with_color(kBlack).with_width(4).with_label("trajectory"));
  map.scatter({tx[0]}, {ty[0]}, Style().with_marker(Marker::kTriangle, 14).with_label("start"));
  Axes& plot = fig.axes(0, 1);
  plot.band(t, sig_lo, sig_hi, Style().with_label("+-2 sigma"))
      .line(t, err, Style().with_label("x error"))
      .hline(0.0, Style().with_dashes().with_width(1.5))
      .title("Position error")
      .xlabel("time [s]")
      .ylabel("error [m]");
  const std::string path = tmp_path("demo_figure.png");
  fig.save_png(path);

  const cv::Mat png = cv::imread(path, cv::IMREAD_COLOR);  // b g r
  ASSERT_FALSE(png.empty());
  EXPECT_EQ(png.cols, 1200);
  EXPECT_EQ(png.rows, 800);
  const auto at = [&](Point p) {
    const cv::Vec3b v = png.at<cv::Vec3b>(static_cast<int>(p.y), static_cast<int>(p.x));
    return Rgb{v[2], v[1], v[0]};
  };
  // Inside the map away from the trajectory: the field's colour; on the trajectory: black.
  const Eigen::Vector2d probe(0.025, 0.025);  // a cell centre
  const Eigen::Vector2i cell = sdf.cell_of(probe);
  EXPECT_EQ(at(map.to_pixel(probe.x(), probe.y())),
            colormap(Colormap::kBlueWhiteRed, (sdf(cell) + m) / (2 * m)));
  EXPECT_EQ(at(map.to_pixel(tx[150], ty[150])), kBlack);  // bottom, clear of the legend
  // The colorbar's top, right of the map, shows the high end of the colormap.
  const PixelRect a = map.plot_area();
  EXPECT_EQ(at({a.x + a.width + 1 + 8 * 2 + 10.0, a.y + 0.0}),
            colormap(Colormap::kBlueWhiteRed, 1.0 - 0.5 / 256));
}

}  // namespace
}  // namespace vdtnav::viz
