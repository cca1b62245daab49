// vdtnav_map_demo: builds the VDT of a floor plan and shows what chapter 2 of the thesis shows:
// DT_x, DT_y, UDT and SDT over the map (Fig. 2.3) and along a line across walls (Fig. 2.4), exact
// and interpolated, with a one-line timing summary.
//
//   vdtnav_map_demo --out DIR                         generated floor plan (embedded default)
//   vdtnav_map_demo --out DIR --map PNG --size WxH    a bitmap floor plan of W x H metres
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/map/map.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/viz/viz.hpp"

namespace {

using namespace vdtnav;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

Grid<float, 2> component(const Grid<Eigen::Vector2f, 2>& vdt, int c) {
  Grid<float, 2> g(vdt.size(), vdt.frame());
  for (std::size_t i = 0; i < vdt.num_cells(); ++i) g[i] = vdt[i][c];
  return g;
}

double max_abs(const Grid<float, 2>& g) {
  double m = 0.0;
  for (float v : g.values())
    if (std::isfinite(v)) m = std::max(m, std::abs(static_cast<double>(v)));
  return m > 0.0 ? m : 1.0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Build the VDT of a floor plan and plot DT_x, DT_y, UDT and SDT (thesis Figs. 2.3, 2.4)"};
  std::string out = "out/map_demo", map_path, size_text;
  double resolution = 0.05, profile_y = std::numeric_limits<double>::quiet_NaN();
  unsigned seed = 1;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--map", map_path, "floor-plan bitmap (dark = occupied); default: generated plan");
  app.add_option("--size", size_text, "world size of --map as WxH metres, e.g. 40x18");
  app.add_option("--resolution", resolution, "cell size in metres")->capture_default_str();
  app.add_option("--seed", seed, "seed of the generated floor plan")->capture_default_str();
  app.add_option("--profile-y", profile_y, "y (metres) of the horizontal profile line");
  CLI11_PARSE(app, argc, argv);

  try {
    std::filesystem::create_directories(out);
    OccupancyGrid<2> occ;
    std::string name;
    if (map_path.empty()) {
      std::printf("[1/4] generating the floor plan (seed %u, %.2f m cells)\n", seed, resolution);
      sim::FloorPlanOptions options;
      options.seed = seed;
      options.resolution = resolution;
      const auto plan = sim::generate_floor_plan(options);
      occ = plan.occupancy;
      name = "generated floor plan (seed " + std::to_string(seed) + ")";
      if (std::isnan(profile_y)) profile_y = plan.rooms.front().centre.y();
    } else {
      double w = 0, h = 0;
      if (std::sscanf(size_text.c_str(), "%lfx%lf", &w, &h) != 2 || w <= 0 || h <= 0) {
        std::fprintf(stderr, "error: --size must be WxH in metres (e.g. 40x18), got '%s'\n",
                     size_text.c_str());
        return 2;
      }
      std::printf("[1/4] loading %s (%g m x %g m, %.2f m cells)\n", map_path.c_str(), w, h,
                  resolution);
      occ = load_occupancy_image(map_path, Eigen::Vector2d(w, h), resolution);
      name = std::filesystem::path(map_path).filename().string();
      if (std::isnan(profile_y)) profile_y = 0.5 * h;
    }
    const Eigen::Vector2i n = occ.size();
    std::printf("      %d x %d cells\n", n.x(), n.y());

    std::printf("[2/4] building the exact VDT and its interpolants\n");
    auto t0 = Clock::now();
    const auto nearest = nearest_occupied_cells(occ);
    const double ms_transform = ms_since(t0);
    t0 = Clock::now();
    const auto map = VdtMap2::build(occ);
    const double ms_map = ms_since(t0);
    const auto vdt = vector_distance_transform<2>(nearest);
    const auto udt = unsigned_distance_transform(nearest);
    const auto sdt = signed_distance_transform(occ);
    const DistanceFieldMap<2> udt_map(udt), sdt_map(sdt);
    const Grid<float, 2> dtx = component(vdt, 0), dty = component(vdt, 1);

    std::printf("[3/4] writing figures of DT_x, DT_y, UDT and SDT\n");
    const double w_m = n.x() * resolution, h_m = n.y() * resolution;
    {
      viz::Figure fig(1600, static_cast<int>(std::clamp(1600.0 * h_m / w_m, 500.0, 1200.0)) + 120,
                      2, 2);
      fig.title("Distance transforms of the " + name);
      struct Panel {
        const Grid<float, 2>* g;
        const char* title;
        viz::Colormap cmap;
        bool symmetric;
      };
      const Panel panels[4] = {{&udt, "(a) UDT [m]", viz::Colormap::kViridis, false},
                               {&sdt, "(b) SDT [m]", viz::Colormap::kBlueWhiteRed, true},
                               {&dtx, "(c) DT_x [m]", viz::Colormap::kBlueWhiteRed, true},
                               {&dty, "(d) DT_y [m]", viz::Colormap::kBlueWhiteRed, true}};
      for (int k = 0; k < 4; ++k) {
        const double m = max_abs(*panels[k].g);
        const double lo = panels[k].symmetric ? -m : 0.0;
        auto& ax = fig.axes(k / 2, k % 2);
        ax.image(viz::heatmap(*panels[k].g, panels[k].cmap, lo, m), 0, w_m, 0, h_m)
            .equal_aspect()
            .colorbar(panels[k].cmap, lo, m)
            .title(panels[k].title)
            .xlabel("x [m]")
            .ylabel("y [m]");
        ax.hline(profile_y, viz::Style().with_color({255, 0, 0}).with_dashes().with_width(1.5));
      }
      fig.save_png(out + "/distance_transforms.png");
      viz::Figure m(1600, static_cast<int>(std::clamp(1600.0 * h_m / w_m, 400.0, 1200.0)) + 60);
      m.axes()
          .image(viz::occupancy_image(occ), 0, w_m, 0, h_m)
          .equal_aspect()
          .title(name)
          .xlabel("x [m]")
          .ylabel("y [m]");
      m.save_png(out + "/map.png");
    }

    std::printf("[4/4] profile along y = %.2f m (exact and interpolated)\n", profile_y);
    std::ofstream csv(out + "/profile.csv");
    csv << "x_m,udt_exact,udt_interp,sdt_exact,sdt_interp,dtx_exact,dtx_interp,dty_exact,dty_"
           "interp\n";
    std::vector<double> xs, cols[8];
    const int samples = 4 * n.x();
    for (int k = 0; k <= samples; ++k) {
      const Eigen::Vector2d p((0.5 + (n.x() - 1.0) * k / samples) * resolution, profile_y);
      const auto exact = map.nearest_point_query(p);  // p - c(cell(p)): no interpolation
      const auto interp = map.evaluate(p);
      const bool inside_obstacle = occ(occ.cell_of(p)) != 0;
      const double u = exact.value.norm();
      // Exact SDT from the stored features: outside, distance to the occupied cell's boundary.
      const double s_exact =
          inside_obstacle ? static_cast<double>(sdt(occ.cell_of(p))) : u - resolution / 2;
      const double row[8] = {u,
                             udt_map.evaluate(p).value,
                             s_exact,
                             sdt_map.evaluate(p).value,
                             exact.value.x(),
                             interp.value.x(),
                             exact.value.y(),
                             interp.value.y()};
      xs.push_back(p.x());
      csv << p.x();
      for (int c = 0; c < 8; ++c) {
        cols[c].push_back(row[c]);
        csv << ',' << row[c];
      }
      csv << '\n';
    }
    viz::Figure fig(1600, 1000, 4, 1);
    fig.title("Along y = " + std::to_string(profile_y).substr(0, 5) +
              " m: exact (stored nearest cell) vs cubic B-spline");
    const char* names[4] = {"UDT [m]", "SDT [m]", "DT_x [m]", "DT_y [m]"};
    for (int k = 0; k < 4; ++k) {
      auto& ax = fig.axes(k, 0);
      ax.line(xs, cols[2 * k], viz::Style().with_color({0, 0, 0}).with_width(3).with_label("exact"))
          .line(xs, cols[2 * k + 1],
                viz::Style()
                    .with_color(viz::kColorCycle[1])
                    .with_width(1.5)
                    .with_label("interpolated"))
          .hline(0.0)
          .ylabel(names[k]);
      if (k == 3) ax.xlabel("x [m]");
    }
    fig.save_png(out + "/profile.png");

    const double cells = static_cast<double>(occ.num_cells());
    std::printf(
        "summary: %d x %d cells; feature transform %.1f ms (%.1f ns/cell); VdtMap build %.1f ms "
        "(%.1f ns/cell); map memory %.1f B/cell -> %s\n",
        n.x(), n.y(), ms_transform, 1e6 * ms_transform / cells, ms_map, 1e6 * ms_map / cells,
        static_cast<double>(map.memory_bytes()) / cells, out.c_str());
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
