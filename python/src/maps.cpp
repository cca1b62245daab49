// Maps in Python: 2D maps (Map2: occupancy, VDT, unknown space) from numpy arrays, ROS map files
// and runs of scans; 3D maps (Map3, dense or sparse) from numpy arrays and every file `vdtnav
// localize3d` reads; the vectorised VDT lookup of both.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "numpy_points.hpp"
#include "results.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/core/file_extension.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/io/vdt_map_file.hpp"
#include "vdtnav/map_files/load_map.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"

namespace vdtnav::python {
namespace {

/// An occupancy array (bool or uint8, nonzero = occupied) of shape (ny, nx) or (nz, ny, nx): the
/// grid's x index is the last array axis (Grid's x-fastest order is numpy's C order).
template <int Dim>
OccupancyGrid<Dim> occupancy_from_array(const py::array& a, double resolution,
                                        const py::handle& origin, double yaw) {
  if (a.ndim() != Dim)
    throw py::value_error("occupancy: expected a " + std::to_string(Dim) + "-D array, got " +
                          std::to_string(a.ndim()) + "-D");
  const char kind = a.dtype().kind();
  if (!(kind == 'b' || (kind == 'u' && a.itemsize() == 1)))
    throw py::value_error("occupancy: expected a bool or uint8 array, got dtype " +
                          std::string(py::str(a.dtype())));
  typename SpaceTraits<Dim>::Index size;
  for (int d = 0; d < Dim; ++d) size[d] = static_cast<int>(a.shape(Dim - 1 - d));
  const typename SpaceTraits<Dim>::Vector o =
      origin.is_none() ? SpaceTraits<Dim>::Vector::Zero().eval()
                       : typename SpaceTraits<Dim>::Vector(to_vector(origin, Dim, "origin"));
  OccupancyGrid<Dim> g(size, GridFrame<Dim>(resolution, o, yaw), 0);
  const auto c = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(a);
  std::transform(c.data(), c.data() + c.size(), g.data(),
                 [](std::uint8_t v) { return static_cast<std::uint8_t>(v != 0); });
  return g;
}

template <typename T, int Dim>
py::array grid_array(const Grid<T, Dim>& g) {
  std::vector<py::ssize_t> shape;
  for (int d = Dim - 1; d >= 0; --d) shape.push_back(g.size()[d]);
  py::array_t<T> a(shape);
  std::copy(g.data(), g.data() + g.num_cells(), a.mutable_data());
  return std::move(a);
}

/// The result of a batch lookup: DT_v, its Jacobian, the inside flags and, when asked, the
/// Hessians; |DT_v| and its gradient are computed from them when first read (a lookup that does
/// not need them does not pay for them).
struct Lookup {
  py::array points;  ///< the array read (the very object passed in: no copy was made)
  py::object value, jacobian = py::none(), inside, hessian = py::none();
  py::object distance_, gradient_;  ///< computed on first access
  int dim = 2;

  py::object distance() {
    if (!distance_) {
      const auto v = py::array_t<double, py::array::forcecast>::ensure(value);
      const py::ssize_t n = v.shape(0);
      py::array_t<double> d(n);
      auto vv = v.unchecked<2>();
      double* out = d.mutable_data();
      for (py::ssize_t i = 0; i < n; ++i) {
        double s = 0.0;
        for (int a = 0; a < dim; ++a) s += vv(i, a) * vv(i, a);
        out[i] = std::sqrt(s);
      }
      distance_ = d;
    }
    return distance_;
  }
  py::object gradient() {
    if (!gradient_) {
      if (jacobian.is_none()) return py::none();
      const auto v = py::array_t<double, py::array::forcecast>::ensure(value);
      const auto j = py::array_t<double, py::array::forcecast>::ensure(jacobian);
      const auto d = py::array_t<double, py::array::forcecast>::ensure(distance());
      const py::ssize_t n = v.shape(0);
      py::array_t<double> g({n, static_cast<py::ssize_t>(dim)});
      auto vv = v.unchecked<2>();
      auto jj = j.unchecked<3>();
      auto dd = d.unchecked<1>();
      auto gg = g.mutable_unchecked<2>();
      // The gradient of |DT_v| = J^T DT_v / |DT_v| (thesis eq. 2.8: J ~ I off the medial axis).
      for (py::ssize_t i = 0; i < n; ++i)
        for (int a = 0; a < dim; ++a) {
          double s = 0.0;
          for (int c = 0; c < dim; ++c) s += jj(i, c, a) * vv(i, c);
          gg(i, a) = dd(i) > 0.0 ? s / dd(i) : 0.0;
        }
      gradient_ = g;
    }
    return gradient_;
  }
};

template <int Dim>
Lookup lookup(const VdtField<Dim>& field, const py::array& points, bool jacobian, bool hessian) {
  using Vector = typename SpaceTraits<Dim>::Vector;
  const PointView<Dim> view(points, "points");
  const auto n = static_cast<py::ssize_t>(view.size());
  Lookup r;
  r.dim = Dim;
  r.points = points;
  py::array_t<double> value({n, py::ssize_t{Dim}}), jac, hess;
  py::array_t<bool> inside(n);
  if (jacobian) jac = py::array_t<double>({n, py::ssize_t{Dim}, py::ssize_t{Dim}});
  if (hessian)
    hess = py::array_t<double>({n, py::ssize_t{Dim}, py::ssize_t{Dim}, py::ssize_t{Dim}});
  double* v = value.mutable_data();
  bool* in = inside.mutable_data();
  double* j = jacobian ? jac.mutable_data() : nullptr;
  double* hs = hessian ? hess.mutable_data() : nullptr;
  {
    py::gil_scoped_release release;
    // Blocks of points converted to doubles and looked up by the batch kernels into samples that
    // stay in the cache, then written once into the arrays.
    constexpr std::size_t kBlock = 128;
    std::array<Vector, kBlock> p;
    std::array<VdtSample<Dim>, kBlock> s;
    for (std::size_t first = 0; first < view.size(); first += kBlock) {
      const std::size_t count = std::min(kBlock, view.size() - first);
      // The points themselves when they are laid out as Eigen's vectors (float64, rows packed,
      // aligned as Eigen requires); else converted into the block.
      const Vector* q = view.template as_vectors<Vector>(first);
      if (q == nullptr) {
        view.read(first, count, p.data());
        q = p.data();
      }
      field.evaluate(q, count, s.data(), jacobian);
      double* vb = v + first * Dim;
      bool* ib = in + first;
      for (std::size_t k = 0; k < count; ++k) {
        for (int a = 0; a < Dim; ++a) vb[k * Dim + a] = s[k].value[a];
        ib[k] = s[k].inside;
      }
      if (jacobian) {  // row-major: [i, c, a] = dDT_c / dp_a
        double* jb = j + first * Dim * Dim;
        for (std::size_t k = 0; k < count; ++k)
          for (int c = 0; c < Dim; ++c)
            for (int a = 0; a < Dim; ++a) jb[(k * Dim + c) * Dim + a] = s[k].jacobian(c, a);
      }
      if (hessian) {
        for (std::size_t k = 0; k < count; ++k) {
          const VdtSampleWithHessian<Dim> h = field.evaluate_with_hessian(q[k]);
          for (int c = 0; c < Dim; ++c)
            Eigen::Map<Eigen::Matrix<double, Dim, Dim, Eigen::RowMajor>>(
                hs + (((first + k) * Dim + c) * Dim) * Dim) = h.hessian[c];
        }
      }
    }
  }
  r.value = value;
  r.inside = inside;
  if (jacobian) r.jacobian = jac;
  if (hessian) r.hessian = hess;
  return r;
}

template <int Dim>
py::dict frame_dict(const GridFrame<Dim>& f, const typename SpaceTraits<Dim>::Index& size) {
  py::dict d;
  d["resolution"] = f.resolution();
  d["origin"] = to_array(Eigen::VectorXd(f.origin()));
  d["yaw"] = f.yaw();
  std::vector<int> s(size.data(), size.data() + Dim);
  d["size"] = s;
  return d;
}

std::shared_ptr<Map2> map2_from_grid(OccupancyGrid<2> occupancy,
                                     std::optional<Grid<std::int8_t, 2>> cells,
                                     std::string source) {
  auto m = std::make_shared<Map2>();
  m->occupancy = std::move(occupancy);
  m->cells = std::move(cells);
  {
    py::gil_scoped_release release;
    m->vdt = std::make_unique<VdtMap2>(VdtMap2::build(m->occupancy));
  }
  if (m->cells) m->knowledge = MapKnowledge(*m->cells);
  m->source = std::move(source);
  return m;
}

std::shared_ptr<Map3> map3_from_grid(const OccupancyGrid<3>& occupancy, bool sparse) {
  auto m = std::make_shared<Map3>();
  py::gil_scoped_release release;
  if (sparse) {
    m->sparse = std::make_unique<SparseVdtMap3>(SparseVdtMap3::build(occupancy));
    m->source = "occupancy array, sparse";
  } else {
    m->dense = std::make_unique<VdtMap3>(VdtMap3::build(occupancy));
    m->source = "occupancy array";
  }
  return m;
}

py::object load_map(const std::filesystem::path& file, double resolution, bool sparse,
                    double margin, const py::object& crop) {
  MapLoadOptions o;
  o.resolution = resolution;
  o.sparse = sparse;
  o.margin = margin;
  if (!crop.is_none()) {
    const Eigen::VectorXd c = to_vector(crop, 6, "crop");
    o.crop = CropBox{c.head<3>(), c.tail<3>()};
  }
  LoadedMap loaded;
  {
    py::gil_scoped_release release;
    loaded = vdtnav::load_map(file.string(), o);
  }
  const std::string source = loaded.source + " " + file.string();
  if (loaded.dimension == 2) {
    auto m = std::make_shared<Map2>();
    m->occupancy = std::move(loaded.occupancy);
    m->vdt = std::move(loaded.vdt);
    // What is known of the map: a map_server map's (and an uncertain map's) unknown cells; a
    // saved VDT map keeps no record of them.
    if (loaded.source != "vdt map file") {
      m->cells = std::move(loaded.ros.cells);
      m->knowledge = MapKnowledge(*m->cells);
    }
    m->source = source;
    return py::cast(m);
  }
  auto m = std::make_shared<Map3>();
  m->dense = std::move(loaded.dense);
  m->sparse = std::move(loaded.sparse);
  m->source = source;
  return py::cast(m);
}

constexpr const char* kLookupDoc = R"doc(
The VDT at each point (thesis eq. 2.5-2.8: DT_v(p) = p - c(p), c the nearest occupied point,
interpolated by the cubic B-spline of eq. 2.9).

points: an N x D array (D = 2 or 3) of float32 or float64 in the map's world frame, any layout
(C or Fortran order, strided slices): it is read in place, not copied.
jacobian: also compute dDT_v/dp and the gradient of the distance (about twice the work).
hessian: also the Hessians of DT_v's D components (one call per point: slower).

Returns a Lookup: value (N x D, DT_v, metres), jacobian (N x D x D, row c the gradient of
component c, or None), inside (N, False where the point lies outside the map and the values are
those of the clamped point), distance (N, |DT_v|) and gradient (N x D, the gradient of |DT_v| = J^T DT_v / |DT_v|), computed
when first read, hessian (N x D x D x D, [k, c] the Hessian of component c, or None) and points
(the array read). The GIL is released during the lookup.
)doc";

}  // namespace

void bind_maps(py::module_& m) {
  py::class_<Lookup>(m, "Lookup", "The result of Map2.lookup / Map3.lookup (see lookup's doc).")
      .def_readonly("points", &Lookup::points, "the array read (the object passed in)")
      .def_readonly("value", &Lookup::value, "N x D: DT_v (metres)")
      .def_property_readonly("distance", &Lookup::distance, "N: |DT_v| (computed on first read)")
      .def_property_readonly("gradient", &Lookup::gradient,
                             "N x D: the gradient of |DT_v| (computed on first read; None "
                             "without the Jacobian)")
      .def_readonly("jacobian", &Lookup::jacobian,
                    "N x D x D: dDT_v/dp, [k, c] the gradient of component c (None when not "
                    "asked for)")
      .def_readonly("inside", &Lookup::inside, "N: False outside the map (clamped values)")
      .def_readonly("hessian", &Lookup::hessian,
                    "N x D x D x D: [k, c] the Hessian of component c (None when not asked for)");

  py::class_<Map2, std::shared_ptr<Map2>>(
      m, "Map2",
      "A 2D map: its occupancy grid, its exact VDT (thesis Ch. 2) and, for maps drawn from scans, "
      "the unknown cells (lost detection does not hold scans into them against the map).")
      .def(py::init([](const py::array& occupancy, double resolution, const py::object& origin,
                       double yaw) {
             return map2_from_grid(occupancy_from_array<2>(occupancy, resolution, origin, yaw),
                                   std::nullopt, "occupancy array");
           }),
           py::arg("occupancy"), py::arg("resolution"), py::arg("origin") = py::none(),
           py::arg("yaw") = 0.0,
           "A map from an occupancy array of shape (ny, nx), bool or uint8 (nonzero: occupied); "
           "cell [j, i] is the square of side `resolution` whose lower-left corner is origin + "
           "R(yaw) (i, j) resolution. Every cell is known (a floor plan).")
      .def_static(
          "from_ros_cells",
          [](const py::array_t<std::int8_t, py::array::c_style | py::array::forcecast>& cells,
             double resolution, const py::object& origin, double yaw) {
            if (cells.ndim() != 2) throw py::value_error("cells: expected a 2-D int8 array");
            const Eigen::Vector2d o = origin.is_none()
                                          ? Eigen::Vector2d::Zero()
                                          : Eigen::Vector2d(to_vector(origin, 2, "origin"));
            Grid<std::int8_t, 2> g(
                Eigen::Vector2i(static_cast<int>(cells.shape(1)), static_cast<int>(cells.shape(0))),
                GridFrame<2>(resolution, o, yaw));
            std::copy(cells.data(), cells.data() + cells.size(), g.data());
            OccupancyGrid<2> occ = occupancy(g);
            return map2_from_grid(std::move(occ), std::move(g), "ros cells");
          },
          py::arg("cells"), py::arg("resolution"), py::arg("origin") = py::none(),
          py::arg("yaw") = 0.0,
          "A map from ROS occupancy values (int8, shape (ny, nx): -1 unknown, 0..100 the "
          "occupancy probability in percent, occupied from 65 as map_server's trinary mode).")
      .def(
          "lookup",
          [](const Map2& self, const py::array& points, bool jacobian, bool hessian) {
            return lookup<2>(*self.vdt, points, jacobian, hessian);
          },
          py::arg("points"), py::arg("jacobian") = true, py::arg("hessian") = false, kLookupDoc)
      .def_property_readonly(
          "occupancy", [](const Map2& self) { return grid_array(self.occupancy); },
          "The occupancy grid, uint8 (ny, nx), 1 = occupied.")
      .def_property_readonly(
          "cells",
          [](const Map2& self) -> py::object {
            if (!self.cells) return py::none();
            return grid_array(*self.cells);
          },
          "The ROS cell values (int8, -1 unknown) or None (every cell known).")
      .def_property_readonly(
          "frame", [](const Map2& self) { return frame_dict(self.vdt->frame(), self.vdt->size()); },
          "resolution, origin (lower-left corner), yaw and size (nx, ny).")
      .def_property_readonly("resolution", [](const Map2& self) { return self.vdt->resolution(); })
      .def_property_readonly("memory_bytes",
                             [](const Map2& self) { return self.vdt->memory_bytes(); })
      .def_readonly("source", &Map2::source)
      .def(
          "save_ros",
          [](const Map2& self, const std::filesystem::path& prefix) {
            if (self.cells) {
              save_ros_map(prefix.string(), *self.cells);
              return;
            }
            Grid<std::int8_t, 2> g(self.occupancy.size(), self.occupancy.frame(), kRosFree);
            for (std::size_t i = 0; i < g.num_cells(); ++i)
              if (self.occupancy[i]) g[i] = kRosOccupied;
            save_ros_map(prefix.string(), g);
          },
          py::arg("prefix"), "Writes PREFIX.yaml and PREFIX.pgm (map_server's format).")
      .def(
          "save_vdt",
          [](const Map2& self, const std::filesystem::path& path) {
            save_vdt_map(path.string(), *self.vdt);
          },
          py::arg("path"), "Writes the VDT map (.vdt, `vdtnav map`'s format).")
      .def("__repr__", [](const Map2& self) {
        return "<vdtnav.Map2 " + std::to_string(self.vdt->size().x()) + " x " +
               std::to_string(self.vdt->size().y()) + " cells of " +
               std::string(py::str("{:g}").format(self.vdt->resolution())) + " m, " + self.source +
               ">";
      });

  py::class_<Map3, std::shared_ptr<Map3>>(
      m, "Map3", "A 3D VDT map, dense (VdtMap3) or sparse (SparseVdtMap3: bricks near surfaces).")
      .def(py::init([](const py::array& occupancy, double resolution, const py::object& origin,
                       bool sparse) {
             return map3_from_grid(occupancy_from_array<3>(occupancy, resolution, origin, 0.0),
                                   sparse);
           }),
           py::arg("occupancy"), py::arg("resolution"), py::arg("origin") = py::none(),
           py::arg("sparse") = false,
           "A map from an occupancy array of shape (nz, ny, nx), bool or uint8; voxel [k, j, i] "
           "has its lowest corner at origin + (i, j, k) resolution.")
      .def(
          "lookup",
          [](const Map3& self, const py::array& points, bool jacobian, bool hessian) {
            return lookup<3>(self.field(), points, jacobian, hessian);
          },
          py::arg("points"), py::arg("jacobian") = true, py::arg("hessian") = false, kLookupDoc)
      .def_property_readonly("sparse", [](const Map3& self) { return self.sparse != nullptr; })
      .def_property_readonly(
          "frame",
          [](const Map3& self) { return frame_dict(self.field().frame(), self.field().size()); })
      .def_property_readonly("resolution",
                             [](const Map3& self) { return self.field().resolution(); })
      .def_property_readonly("memory_bytes",
                             [](const Map3& self) {
                               return self.dense ? self.dense->memory_bytes()
                                                 : self.sparse->memory_bytes();
                             })
      .def_readonly("source", &Map3::source)
      .def("__repr__", [](const Map3& self) {
        const auto& s = self.field().size();
        return "<vdtnav.Map3 " + std::to_string(s.x()) + " x " + std::to_string(s.y()) + " x " +
               std::to_string(s.z()) + " voxels of " +
               std::string(py::str("{:g}").format(self.field().resolution())) + " m, " +
               self.source + ">";
      });

  m.def("load_map", &load_map, py::arg("path"), py::arg("resolution") = 0.0,
        py::arg("sparse") = false, py::arg("margin") = 1.0, py::arg("crop") = py::none(),
        "Loads any map file the CLI loads (vdtnav::load_map): a ROS map YAML (.yaml: a Map2 with "
        "its unknown cells), an uncertain map file (.umap) or a 2D .vdt (Map2); a 3D .vdt, .svdt, "
        "OctoMap (.bt, .ot) or point cloud (.pcd, .ply, "
        ".vtk, .xyz/.txt/.csv) as a Map3. resolution: the voxel edge for clouds (0: 0.1 m) and "
        "octrees (0: their leaf size); sparse: build a SparseVdtMap3; margin: free border around "
        "a cloud or octree, metres; crop: (xmin, ymin, zmin, xmax, ymax, zmax), the cloud points "
        "kept "
        "(`--crop`). Raises vdtnav.IoError / FormatError (file, line, what was "
        "expected).");

  m.def(
      "build_occupancy_map",
      [](const py::object& poses, const py::sequence& scans, double resolution) {
        const auto p = to_matrix(poses, static_cast<py::ssize_t>(py::len(scans)), 3, "poses");
        std::vector<Pose2> ps;
        std::vector<LaserScan> ss;
        for (py::ssize_t k = 0; k < p.rows(); ++k) {
          ps.push_back(p.row(k).transpose());
          ss.push_back(scans[static_cast<std::size_t>(k)].cast<LaserScan>());
          check_scan(ss.back(), "scans");
        }
        mapping::OccupancyMapperOptions o;
        o.resolution = resolution;
        mapping::OccupancyMap map;
        {
          py::gil_scoped_release release;
          map = mapping::build_occupancy_map(ps, ss, o);
        }
        return map2_from_grid(std::move(map.occupancy), std::move(map.cells),
                              "occupancy map of " + std::to_string(ss.size()) + " scans");
      },
      py::arg("poses"), py::arg("scans"), py::arg("resolution") = 0.05,
      "A map drawn from scans at known poses (`vdtnav map`): log-odds ray casting (OctoMap's "
      "hit/miss probabilities), poses N x 3 (x, y, phi) and N LaserScans; unknown cells kept.");
}

}  // namespace vdtnav::python
