// vdtnav: the command-line tool. Build maps from logs, localize logs on maps with any of the
// five methods, and evaluate trajectories against relations or reference trajectories.
//   vdtnav map       --log LOG --resolution R --out PREFIX [--from T0 --to T1]
//                    [--time-base logger|ipc]
//   vdtnav localize  --map MAP.yaml --log LOG [--method M] [--init x,y,yaw] --out TRAJ.tum
//                    [--cov POSES.csv] [--all-poses | --accept-status LIST] [--from T0 --to T1]
//                    [--time-base logger|ipc] [--strict] [--plot PREFIX]
//   vdtnav eval      --traj TRAJ.tum (--relations REL | --reference REF.tum) [--cov COV.csv]
//                    [--max-gap S] [--json]
//   vdtnav join-odometry  (the Intel lab converter; see `vdtnav join-odometry --help`)
//   vdtnav map3d      --map CLOUD|OCTREE --out MAP.vdt [--resolution R] [--crop BOX]
//   vdtnav localize3d --map MAP --scan SCAN... | --scans DIR [--init x,y,z,r,p,y | --init-matrix F]
//                     [--dof 6|4 [--attitude-sigma S]] [--voxel V] [--out YAML|DIR]
//                     [--multi-start] [--config F] [--strict]
//   (map3d and localize3d when the point cloud front ends were built)
// Exit status (exit_status.hpp): 0 done, 1 bad input, 2 bad usage, 3 completed but nothing
// localized (or --strict and a scan lost). Outputs appear only when a run completes
// (staged_output.hpp).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "common.hpp"
#include "exit_status.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/map_files/load_map.hpp"

int main(int argc, char** argv) {
  CLI::App app{"vdtnav: robot localization on Vector Distance Transform maps"};
  app.require_subcommand(1);
  vdtnav::tools::add_map_command(app);
  vdtnav::tools::add_localize_command(app);
  vdtnav::tools::add_eval_command(app);
  vdtnav::tools::add_join_odometry_command(app);
#ifdef VDTNAV_CLI_3D
  vdtnav::tools::add_map3d_command(app);
  vdtnav::tools::add_localize3d_command(app);
#endif
#ifdef VDTNAV_CLI_ROS
  vdtnav::tools::add_bag_command(app);
#endif
  using namespace vdtnav::tools;  // NOLINT(google-build-using-namespace): the exit statuses
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --help-all, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {  // unknown option, a check failed, a value missing
    app.exit(e);                        // prints CLI11's message and hint
    return kExitUsage;
  } catch (const NotLocalized& e) {
    std::fprintf(stderr, "vdtnav: %s\n", e.what());
    return kExitNotLocalized;
  } catch (const UsageError& e) {  // an option's value or a combination out of its domain
    std::fprintf(stderr, "vdtnav: error: %s\n", e.what());
    return kExitUsage;
  } catch (const vdtnav::MapOptionError& e) {  // the same, found by the map loader
    std::fprintf(stderr, "vdtnav: error: %s\n", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {  // files missing, unreadable or not in their format;
                                       // settings files with unknown keys or wrong values
    std::fprintf(stderr, "vdtnav: error: %s\n", e.what());
    return kExitBadInput;
  }
  return kExitOk;
}
