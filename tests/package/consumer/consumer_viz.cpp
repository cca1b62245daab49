// A user's program against the installed vdtnav::viz: draw, then write a PNG.
#include <vdtnav/viz/image.hpp>

#include <cstdio>
#include <fstream>

int main(int argc, char** argv) {
  using namespace vdtnav::viz;
  if (argc < 2) return 2;
  RgbImage img(40, 20);
  fill_rect(img, PixelRect{10, 5, 8, 4}, Rgb{255, 0, 0});
  write_png(argv[1], img);
  std::ifstream in(argv[1], std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  const bool ok = img.at(12, 6) == Rgb{255, 0, 0} && img.at(2, 2) == kWhite && in.gcount() == 8 &&
                  sig[1] == 'P' && sig[2] == 'N' && sig[3] == 'G';
  std::printf("image and PNG: %s\n", ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
