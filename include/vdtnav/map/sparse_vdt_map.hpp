#pragma once
/// \file
/// \brief `SparseVdtMap3`: the continuous 3D VDT map stored in 8^3-voxel bricks near the surfaces
/// only, with a coarse dense level everywhere else ("large maps (tiled or sparse grids)", SPEC).
///
/// Fine level: the same interpolating cubic B-spline of DT_v(p) = p - c(p) as VdtMap3 (one float
/// coefficient per component per node), but only the nodes of allocated bricks are stored, each
/// node once (8^3 nodes x 3 floats = 6 KiB a brick). A brick is allocated when its nodes are
/// needed by a query within `band` voxels of a surface voxel (its 4^3 support). A flat table over
/// the brick lattice (4 B per 512 voxels) maps a brick coordinate to its slot, or -1.
///
/// Prefilter: the spline's prefilter (c_{k-1} + 4 c_k + c_{k+1}) / 6 = f_k is global, but its
/// influence decays by 2 - sqrt(3) ~ 0.268 per node. The build solves it on tiles of 64^3 voxels
/// widened by `prefilter_overlap` nodes (8: 0.268^8 ~ 3e-5 of a sample's difference), with the
/// dense map's natural ends where a tile reaches the map's border, and keeps the nodes of the
/// tile's bricks: every node has one coefficient, so the fine spline is one C^2 field across
/// bricks and agrees with VdtMap3::build of the same occupancy up to that truncation.
///
/// Coarse level (8x the resolution, one node per brick, at the brick's centre): the nearest surface
/// voxel of each node. A query whose support is not allocated is answered by the SPEC's exact
/// alternative at that scale: DT_v(p) = p - c with c the nearest to p of the 8 surrounding nodes'
/// surface voxels, Jacobian = identity. Finite everywhere in the box, pointing away from the
/// surfaces, |DT_v| exact where the nearest surface voxel is one of those candidates (the
/// estimators' gates drop such far points anyway). A coarse B-spline of DT_v was tried first and
/// rejected: at 8 voxels a node it averages across every cut locus near it (the generated room:
/// DT_v pointed away from the nearest surface at 85 % of the coarse points, against 96 % now,
/// and |DT_v| grew along DT_v at 47 %, against 100 %).
///
/// Memory: 6 KiB per allocated brick + 16 B per brick of the box (index + coarse node).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/vdt_field.hpp"
#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav {

/// \brief How a sparse map is built.
struct SparseVdtMapOptions {
  /// Voxels (finite, in [0, 16]): every query point within `band` voxels of a surface voxel's
  /// centre is answered by the fine level (bricks are allocated for its whole 4^3 support).
  /// 3 (0.15 m at 0.05 m: 5 sigma of a 3 cm LiDAR's range noise) keeps the CATEC OctoMap at
  /// 96 MB (15 489 bricks); 4 takes it to 104 MB.
  double band = 3.0;
  /// Nodes (in [0, 16]) by which each tile's prefilter window overlaps its neighbours; 8 gives
  /// ~3e-5 of the dense map's coefficients. Smaller values only exist to show what it buys.
  int prefilter_overlap = 8;
  /// As VdtMap::build: false = the features are the surface voxels (occupied voxels with a free
  /// 6-neighbour inside the box), true = every occupied voxel.
  bool all_occupied_cells = false;
};

/// \brief Sparse continuous 3D VDT map with the lookup interface of VdtMap3.
///
/// Copies share the (immutable) bricks. Queries outside the box are clamped (inside = false) as
/// VdtMap3's are.
class SparseVdtMap3 final : public VdtField<3> {
 public:
  using Vector = Eigen::Vector3d;
  using Matrix = Eigen::Matrix3d;
  using Index = Eigen::Vector3i;

  static constexpr int kBrick = 8;                              ///< voxels per brick edge
  static constexpr int kBrickNodes = kBrick * kBrick * kBrick;  ///< 512
  static constexpr int kBrickFloats = 3 * kBrickNodes;          ///< DT_x, DT_y, DT_z per node
  static constexpr int kTile = 64;  ///< voxels per edge of a build tile (8 bricks)

  /// \brief The bricks as arrays, and whoever keeps them alive (a vector or a file mapping).
  struct Bricks {
    /// per brick of the box (x fastest): its slot, or -1
    const std::int32_t* index = nullptr;
    /// per slot kBrickFloats: 8^3 nodes, x fastest, (DT_x, DT_y, DT_z) interleaved
    const float* coefficients = nullptr;
    /// per brick of the box (x fastest): the voxel index (x, y, z) of the surface voxel nearest to
    /// the brick's centre (the coarse level)
    const std::int32_t* coarse = nullptr;
    std::size_t num_bricks = 0;  ///< slots
    std::shared_ptr<const void> owner;
  };

  SparseVdtMap3() = default;

  /// \brief Assembles a map from its parts (map files). Checks the index's and the coarse
  /// voxels' ranges. \throws ConfigError when they are out of range.
  SparseVdtMap3(const GridFrame<3>& frame, const Index& size, double band, Bricks bricks);

  /// \brief Builds the map of a set of occupied voxels without a dense grid at full resolution.
  /// \param occupied voxel indices in [0, size) (duplicates allowed).
  /// \param frame placement of voxel (0,0,0) (as Grid's).
  /// \param size voxels per axis, each >= 4.
  /// \throws ConfigError for an option out of its domain, a voxel outside the box, no occupied
  ///         voxel, or a box of 2^31 bricks or more.
  [[nodiscard]] static SparseVdtMap3 build(const std::vector<Index>& occupied,
                                           const GridFrame<3>& frame, const Index& size,
                                           const SparseVdtMapOptions& options = {});

  /// \brief build() from the occupied voxels of a dense grid (tests, small maps).
  [[nodiscard]] static SparseVdtMap3 build(const OccupancyGrid<3>& occupancy,
                                           const SparseVdtMapOptions& options = {});

  /// \brief Interpolated DT_v and Jacobian at world point p.
  [[nodiscard]] VdtSample<3> evaluate(const Vector& p) const {
    VdtSample<3> s;
    evaluate(&p, 1, &s);
    return s;
  }

  /// \brief evaluate() at n points (out[k] for p[k]) with the kernels of simd_level(), as
  /// VdtMap3::evaluate (AVX2 results differ from the portable ones by float rounding); points
  /// answered by the coarse level take the portable path. Without `jacobian` only the values and
  /// the inside flags are written.
  void evaluate(const Vector* p, std::size_t n, VdtSample<3>* out,
                bool jacobian = true) const override;

  /// \brief DT_v, its Jacobian and its Hessians at p. The Hessians are central differences of
  /// the analytic Jacobian over +-resolution/20 (the spline is C^2: the error is O(h^2) of its
  /// third derivative, ~1e-3 of a Hessian of 1/resolution); what the implicit-function covariance
  /// needs, once per reading and solve.
  [[nodiscard]] VdtSampleWithHessian<3> evaluate_with_hessian(const Vector& p) const override;

  /// \brief The exact alternative (as VdtMap3's): DT_v(p) = p - c(cell(p)) from the stored nearest
  /// surface voxel of the cell containing p, recovered from the spline's value at that node
  /// (it interpolates the integer offsets exactly). Exact for cells within `band` + sqrt(3)/2
  /// voxels of the surface; elsewhere c is the coarse level's.
  [[nodiscard]] VdtSample<3> nearest_point_query(const Vector& p) const override;

  /// \return true when the fine level (the bricks) answers a query at p.
  [[nodiscard]] bool fine_level(const Vector& p) const;

  [[nodiscard]] const GridFrame<3>& frame() const noexcept override { return frame_; }
  [[nodiscard]] const Index& size() const noexcept override { return size_; }
  [[nodiscard]] double resolution() const noexcept { return frame_.resolution(); }
  [[nodiscard]] double band() const noexcept { return band_; }
  /// \return bricks per axis, ceil(size / kBrick).
  [[nodiscard]] const Index& brick_grid_size() const noexcept { return bricks_size_; }
  [[nodiscard]] const Bricks& bricks() const noexcept { return bricks_; }
  /// \return bytes held by the map: bricks, brick index and coarse level.
  [[nodiscard]] std::size_t memory_bytes() const noexcept;

 private:
  /// Fine-level DT_v (and Jacobian) in grid axes per unit index at clamped continuous index u.
  /// \return false when a brick of the support is not allocated.
  bool evaluate_fine(const Vector& u, Vector* value, Matrix* jacobian) const;
  /// The coarse level's surface voxel for clamped continuous index u.
  Index coarse_nearest(const Vector& u) const;
  /// One point, world in and out.
  VdtSample<3> evaluate_one(const Vector& p, bool jacobian) const;

  GridFrame<3> frame_;
  Index size_ = Index::Zero();
  Index bricks_size_ = Index::Zero();
  double band_ = 0.0;
  Bricks bricks_;
};

}  // namespace vdtnav
