// A personal mobility device localized outdoors with a rear RGB-D camera (thesis 3.4.5, Dataset
// 5; Figs. 3.19-3.24): a scooter drives along the paths of a generated park; every frame is
// rendered from the true pose (textured grass, pavement and gravel, obstacles standing on the
// ground and their shadows, depth noise and holes, and a light that differs from the mapping
// day), the boundaries between ground surfaces are extracted without a neural network and
// back-projected with depth, and four filters run side by side on the same frames:
//   vdt-ekf            the VDT EKF with the boundary points (3.23-3.24, corrected per SPEC),
//   vdt-ekf+bearings   the same filter also fed bearings to known landmarks (lamp posts, signs),
//   bearings           the landmark-only EKF (the framework the thesis augmented),
//   odometry           dead reckoning.
//
//   vdtnav_pmd_rgbd [--out DIR] [--seed N] [--frames N] [--verbose]
//                   [--map-correlation-length M] [--schmidt-map-errors] [--correction-gate G]
//   vdtnav_pmd_rgbd --kinect FRAMES_DIR [--calibration FILE] [--out DIR]
//
// Writes DIR/table.csv (method,frames,pos_rmse_m,yaw_rmse_rad,anees,anees_lo,anees_hi,
// within_2sigma_pct,ms_per_frame,anees_left_out,ms_median,ms_p99,ms_max,nees_inside_95_pct),
// table.md, errors.png
// (Fig. 3.23: errors with +-2 sigma), trajectories.png (Fig. 3.24) and frame.png (one frame with
// its kept and pruned boundaries). With --kinect, instead: relative localization between recorded
// RGB-D frames (color/{1..5}.png, depth/{1..5}.pgm in mm, pose.txt camera-to-world "tx ty tz qx qy
// qz qw"): each frame's boundary points on a VDT map of the other frames' points, drawn through the
// given poses on the fitted floor, reported against the given poses in DIR/kinect_relative.csv.
//
// The machinery (scenario, run, table, figures, the Kinect study) is declared in pmd_study.hpp.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "pmd_study.hpp"

int main(int argc, char** argv) {
  CLI::App app{"PMD localization with RGB-D ground boundaries and landmark bearings (3.4.5)"};
  std::string out = "out/pmd_rgbd";
  std::uint64_t seed = 1;
  std::size_t frames = 0;
  bool verbose = false;
  double correlation_length = 2.0;
  bool schmidt = false;
  double correction_gate = 11.34;  // chi-square(3)'s 99 % point
  std::string kinect, calibration;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--seed", seed, "seed of the park, the drive and all noise")
      ->capture_default_str();
  app.add_option("--frames", frames, "frames to run (0: the whole ~500 m drive)")
      ->capture_default_str();
  app.add_flag("--verbose", verbose, "one line per frame");
  app.add_option("--map-correlation-length", correlation_length,
                 "side of the squares whose map errors are shared (m, 0: independent)")
      ->capture_default_str();
  app.add_flag("--schmidt-map-errors", schmidt,
               "carry the squares' map errors from frame to frame (VdtEkfOptions::"
               "schmidt_map_errors) instead of reporting each frame's map term on top");
  app.add_option("--correction-gate", correction_gate,
                 "refuse a frame's correction larger than this chi-square(3) value under the "
                 "prior (VdtEkfOptions::correction_gate; 0: off)")
      ->capture_default_str();
  app.add_option("--kinect", kinect,
                 "instead: relative localization between the recorded RGB-D frames of this folder")
      ->check(CLI::ExistingDirectory);
  app.add_option("--calibration", calibration,
                 "with --kinect: the camera's calibration file (default: Kinect v1 intrinsics)")
      ->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);

  try {
    if (!kinect.empty()) return pmd_study::kinect_study(kinect, calibration, out);
    std::filesystem::create_directories(out);
    const pmd_study::Scenario sc = pmd_study::make_scenario(seed, frames);
    const pmd_study::FilterRun run =
        pmd_study::run_filters(sc, correlation_length, schmidt, correction_gate, seed, verbose);
    pmd_study::write_tables(out, sc, run);
    pmd_study::draw_figures(out, sc, run);
    std::printf("[done] %s/table.csv, table.md, errors.png, trajectories.png, frame.png\n",
                out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vdtnav_pmd_rgbd: %s\n", e.what());
    return 1;
  }
  return 0;
}
