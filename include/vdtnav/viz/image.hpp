#pragma once
/// \file
/// \brief `RgbImage`, an 8-bit RGB raster, with anti-aliased drawing primitives and PNG output.
///
/// Drawing uses continuous pixel coordinates: pixel (i, j) covers [i, i+1) x [j, j+1), so its
/// centre is (i + 0.5, j + 0.5); x grows to the right, y grows *down*. Everything is clipped to the
/// image. Shapes are drawn by OpenCV's imgproc (cv::fillPoly, cv::circle) at 4 x 4
/// sub-pixels per pixel, averaged to an anti-aliased coverage mask and blended once into the image;
/// OpenCV stays inside the library.

#include <cstdint>
#include <string>
#include <vector>

namespace vdtnav::viz {

/// \brief An 8-bit sRGB colour.
struct Rgb {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;

  friend constexpr bool operator==(const Rgb& a, const Rgb& b) {
    return a.r == b.r && a.g == b.g && a.b == b.b;
  }
  friend constexpr bool operator!=(const Rgb& a, const Rgb& b) { return !(a == b); }
};

inline constexpr Rgb kBlack{0, 0, 0};
inline constexpr Rgb kWhite{255, 255, 255};

/// \brief A point in continuous pixel coordinates (see the file comment).
struct Point {
  double x = 0.0;
  double y = 0.0;
};

/// \brief An integer rectangle of pixels: columns [x, x + width), rows [y, y + height).
struct PixelRect {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;

  [[nodiscard]] bool contains(int px, int py) const {
    return px >= x && py >= y && px < x + width && py < y + height;
  }
};

/// \brief A row-major 8-bit RGB image, row 0 at the top, 3 bytes per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3 bytes, r g b per pixel

  RgbImage() = default;
  /// \brief A width x height image filled with `fill` (throws ConfigError on negative sizes).
  RgbImage(int width, int height, Rgb fill = kWhite);

  [[nodiscard]] bool contains(int x, int y) const {
    return x >= 0 && y >= 0 && x < width && y < height;
  }
  /// \return the colour of pixel (x, y), which must be inside.
  [[nodiscard]] Rgb at(int x, int y) const;
  /// \brief Sets pixel (x, y); no-op outside the image.
  void set(int x, int y, Rgb c);
};

/// \brief Marker shapes for scatter plots and legends.
enum class Marker { kNone, kCircle, kSquare, kTriangle, kCross, kPlus };

/// \brief Fills (blends with alpha) the pixels of `rect`.
void fill_rect(RgbImage& img, const PixelRect& rect, Rgb c, double alpha = 1.0);
/// \brief Draws the outline of `rect`, `thickness` pixels wide, inside the rectangle.
void draw_rect(RgbImage& img, const PixelRect& rect, Rgb c, int thickness = 1);

/// \brief Anti-aliased segment from a to b with round caps.
/// \param width stroke width in pixels (to a quarter pixel).
void draw_line(RgbImage& img, Point a, Point b, Rgb c, double width = 1.0, double alpha = 1.0);

/// \brief Anti-aliased polyline with round joins; each pixel is blended once, so overlapping
/// segments of a translucent line do not darken. `dashed` draws dashes scaled with the width.
void draw_polyline(RgbImage& img, const std::vector<Point>& pts, Rgb c, double width = 1.0,
                   double alpha = 1.0, bool dashed = false);

/// \brief Anti-aliased filled disc.
void fill_circle(RgbImage& img, Point centre, double radius, Rgb c, double alpha = 1.0);

/// \brief Anti-aliased filled polygon (cv::fillPoly); suitable for large translucent bands.
void fill_polygon(RgbImage& img, const std::vector<Point>& pts, Rgb c, double alpha = 1.0);

/// \brief Draws a marker of diameter `size` pixels centred at `centre`.
void draw_marker(RgbImage& img, Point centre, Marker marker, double size, Rgb c,
                 double alpha = 1.0);

/// \brief Copies `src` with its top-left corner at (x, y), clipped to `dst`.
void blit(RgbImage& dst, const RgbImage& src, int x, int y);

/// \brief Draws `src` stretched (nearest neighbour) over the continuous rectangle
/// [x0, x1] x [y0, y1] of `dst`; crisp cells, as wanted for maps.
void draw_scaled(RgbImage& dst, const RgbImage& src, double x0, double y0, double x1, double y1);

/// \brief Writes `img` as an 8-bit RGB PNG (whatever the file name's extension).
/// \throws vdtnav::IoError naming `path` if the file cannot be written.
void write_png(const std::string& path, const RgbImage& img);

}  // namespace vdtnav::viz
