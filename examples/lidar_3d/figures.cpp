// The figures: trajectory.png (the top view over the footprint) and errors.png (each run's
// errors with +-2 sigma of its reported covariance).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "lidar_3d_study.hpp"
#include "vdtnav/viz/plot.hpp"

namespace lidar3d {

using namespace vdtnav;

void draw_figures(const std::string& out, const Footprint& fp,
                  const std::vector<sim::TimedPose>& tour, const std::vector<Pose3>& truth,
                  const Run (&runs)[kRuns]) {
  {
    const OccupancyGrid<2>& b = fp.blocked;
    viz::RgbImage img(b.size().x(), b.size().y());
    for (int j = 0; j < b.size().y(); ++j)
      for (int i = 0; i < b.size().x(); ++i)
        if (b(Eigen::Vector2i(i, j)) != 0)
          img.set(i, b.size().y() - 1 - j, viz::Rgb{170, 170, 170});
    const Eigen::Vector2d lo = b.frame().origin();
    const Eigen::Vector2d hi = lo + b.resolution() * b.size().cast<double>();
    viz::Figure fig(1300, 1100);
    viz::Axes& ax = fig.axes();
    ax.image(img, lo.x(), hi.x(), lo.y(), hi.y()).equal_aspect();
    const auto xy = [&](const std::vector<Pose3>& ps, std::vector<double>& xs,
                        std::vector<double>& ys) {
      for (const Pose3& p : ps) {
        xs.push_back(p.translation().x());
        ys.push_back(p.translation().y());
      }
    };
    std::vector<double> tx, ty;
    xy(truth, tx, ty);
    ax.line(tx, ty, viz::Style().with_color(viz::kBlack).with_label("truth"));
    for (const Run& r : runs) {
      std::vector<double> xs, ys;
      xy(r.estimates, xs, ys);
      ax.line(xs, ys, viz::Style().with_width(1.5).with_label(r.name));
    }
    ax.title("Top view: the footprint (grey: blocked from floor + 0.2 m to 2 m)")
        .xlabel("x (m)")
        .ylabel("y (m)")
        .legend(viz::LegendLocation::kUpperRight);
    fig.save_png(out + "/trajectory.png");
  }
  {
    viz::Figure fig(1600, 2200, kRuns, 2);
    fig.title("Errors against the truth, with +-2 sigma of the reported covariance (bands)");
    std::vector<double> t;
    for (const sim::TimedPose& p : tour) t.push_back(p.t);
    for (int m = 0; m < kRuns; ++m) {
      for (int part = 0; part < 2; ++part) {  // position (m), attitude (rad)
        viz::Axes& ax = fig.axes(m, part);
        const char* axis_names[3] = {part == 0 ? "x" : "roll", part == 0 ? "y" : "pitch",
                                     part == 0 ? "z" : "yaw"};
        for (int c = 0; c < 3; ++c) {
          std::vector<double> e, lo, hi;
          for (std::size_t k = 0; k < runs[m].estimates.size(); ++k) {
            const Vector6d d = ominus(runs[m].estimates[k], truth[k]);
            const double s =
                std::sqrt(std::max(0.0, runs[m].covariances[k](3 * part + c, 3 * part + c)));
            e.push_back(d[3 * part + c]);
            lo.push_back(-2.0 * s);
            hi.push_back(2.0 * s);
          }
          const std::vector<double> tm(t.begin(), t.begin() + static_cast<long>(e.size()));
          ax.band(tm, lo, hi, viz::Style());
          ax.line(tm, e, viz::Style().with_width(1.2).with_label(axis_names[c]));
        }
        ax.title(runs[m].name + (part == 0 ? ": position, m" : ": attitude, rad"))
            .xlabel("time (s)")
            .legend(viz::LegendLocation::kUpperRight);
      }
    }
    fig.save_png(out + "/errors.png");
  }
}

}  // namespace lidar3d
