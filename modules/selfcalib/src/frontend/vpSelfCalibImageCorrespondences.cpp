/*
 * ViSP SelfCalib: from images to the observations a calibration runs on (front end, views left
 * out, method choice).
 */
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <utility>

#include <visp3/io/vpImageIo.h>

#include "../pipeline/vpSelfCalibPipelines.h" // measuredStart

#include <opencv2/imgproc.hpp>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

bool vpSelfCalibImageCorrespondences::needsFrontEnd(const vpSelfCalibDataset &dataset)
{
  for (const vpSelfCalibDataset::View &v : dataset.views)
    if (v.points.empty() && !v.image.empty())
      return true;
  return false;
}

vpFeatureFrontEnd::Prior vpSelfCalibImageCorrespondences::makePrior(const vpKinematicChain &model,
                                                                   const vpSelfCalibDataset &dataset)
{
  vpFeatureFrontEnd::Prior prior;
  for (const vpSelfCalibDataset::View &v : dataset.views) {
    if (v.q.size() == model.getNumJoints() && v.q.size() > 0)
      prior.fMc.push_back(model.get_fMc(v.q));
    else if (v.q.size() == 0 && v.has_fMe)
      prior.fMc.push_back(v.fMe * model.get_eMc());
    else
      return vpFeatureFrontEnd::Prior();
  }
  prior.cam = dataset.cam;
  return prior;
}

namespace
{
/*
  The epipolar residual of one match (pixel a in view i, pixel b in view k) under the robot's
  end-effector motion A = e_kMe_i and eMc: the camera's motion c_kMc_i = eMc^-1 A eMc = (R, t),
  E = [t]x R, the Sampson distance of the normalized rays x_a = ((u - u0) / f, (v - v0) / (mu f), 1)
  and x_b, in px (f fixed):
      r = f (x_b^T E x_a) / sqrt((E x_a)_1^2 + (E x_a)_2^2 + (E^T x_b)_1^2 + (E^T x_b)_2^2).
  eMc = (R0 exp([w]x), t0 + dt) about the measured start (R0, t0). (f is not refined here: with the
  robot's own error left in the residual, the epipolar distance is smallest at a wrong f, small in
  px, large in normalized units.)
*/
struct EpipolarThroughRobot {
  Eigen::Matrix3d RA, R0;
  Eigen::Vector3d tA, t0;
  //! The pair's essential matrix E at eMc = (R0 exp([w]x), t0 + dt).
  template <typename T> Eigen::Matrix<T, 3, 3> essential(const T *w, const T *dt) const
  {
    using M3 = Eigen::Matrix<T, 3, 3>;
    using V3 = Eigen::Matrix<T, 3, 1>;
    M3 dR;
    ceres::AngleAxisToRotationMatrix(w, dR.data());
    const M3 Rc = R0.cast<T>() * dR;
    const V3 tc = t0.cast<T>() + V3(dt[0], dt[1], dt[2]);
    // c_kMc_i = eMc^-1 A eMc: R = Rc^T RA Rc, t = Rc^T (RA tc + tA - tc).
    const M3 R = Rc.transpose() * RA.cast<T>() * Rc;
    const V3 t = Rc.transpose() * (RA.cast<T>() * tc + tA.cast<T>() - tc);
    M3 tx;
    tx << T(0), -t(2), t(1), t(2), T(0), -t(0), -t(1), t(0), T(0);
    return tx * R;
  }
  //! The residual of the normalized rays a and b under E, in px at the focal length f.
  template <typename T>
  static T sampson(const Eigen::Matrix<T, 3, 3> &E, const Eigen::Vector3d &a, const Eigen::Vector3d &b, double f)
  {
    using V3 = Eigen::Matrix<T, 3, 1>;
    const V3 xa = a.cast<T>(), xb = b.cast<T>();
    const V3 Ea = E * xa, Etb = E.transpose() * xb;
    const T den = Ea(0) * Ea(0) + Ea(1) * Ea(1) + Etb(0) * Etb(0) + Etb(1) * Etb(1);
    return T(f) * xb.dot(Ea) / ceres::sqrt(den + T(1e-30));
  }
};

/*
  A pair's essential matrix, kept for the last parameter value it was asked at, as a value and as
  Ceres Jets (the derivatives in w, then dt, as AutoDiffCostFunction<., 1, 3, 3> seeds them): the
  pair's residual blocks, evaluated one after the other, compute it once instead of once each. The
  residuals and Jacobians are those of automatic differentiation of the whole residual. Not for a
  solver that evaluates on several threads.
*/
class PairEssential
{
public:
  using Jet = ceres::Jet<double, 6>;
  explicit PairEssential(const EpipolarThroughRobot &motion) : motion_(motion) {}
  const Eigen::Matrix3d &at(const double *w, const double *dt)
  {
    if (!same(value_key_, w, dt)) {
      value_ = motion_.essential(w, dt);
      keep(value_key_, w, dt);
    }
    return value_;
  }
  const Eigen::Matrix<Jet, 3, 3> &jetsAt(const double *w, const double *dt)
  {
    if (!same(jet_key_, w, dt)) {
      Jet jw[3], jdt[3];
      for (int c = 0; c < 3; ++c) {
        jw[c] = Jet(w[c], c);
        jdt[c] = Jet(dt[c], 3 + c);
      }
      jets_ = motion_.essential(jw, jdt);
      keep(jet_key_, w, dt);
    }
    return jets_;
  }

private:
  using Key = std::array<double, 7>; // w, dt, and 1 once set
  static bool same(const Key &k, const double *w, const double *dt)
  {
    return k[6] == 1 && std::equal(w, w + 3, k.begin()) && std::equal(dt, dt + 3, k.begin() + 3);
  }
  static void keep(Key &k, const double *w, const double *dt)
  {
    std::copy(w, w + 3, k.begin());
    std::copy(dt, dt + 3, k.begin() + 3);
    k[6] = 1;
  }
  EpipolarThroughRobot motion_;
  Key value_key_{}, jet_key_{};
  Eigen::Matrix3d value_;
  Eigen::Matrix<Jet, 3, 3> jets_;
};

//! One match's epipolar residual (EpipolarThroughRobot) on its pair's shared essential matrix.
class EpipolarCost : public ceres::SizedCostFunction<1, 3, 3>
{
public:
  EpipolarCost(std::shared_ptr<PairEssential> pair, const Eigen::Vector3d &a, const Eigen::Vector3d &b, double f)
    : pair_(std::move(pair)), a_(a), b_(b), f_(f)
  {
  }
  bool Evaluate(double const *const *p, double *residuals, double **jacobians) const override
  {
    if (!jacobians) {
      residuals[0] = EpipolarThroughRobot::sampson<double>(pair_->at(p[0], p[1]), a_, b_, f_);
      return true;
    }
    const PairEssential::Jet r = EpipolarThroughRobot::sampson<PairEssential::Jet>(pair_->jetsAt(p[0], p[1]), a_, b_, f_);
    residuals[0] = r.a;
    for (int block = 0; block < 2; ++block)
      if (jacobians[block])
        for (int c = 0; c < 3; ++c)
          jacobians[block][c] = r.v[3 * block + c];
    return true;
  }

private:
  std::shared_ptr<PairEssential> pair_;
  Eigen::Vector3d a_, b_;
  double f_;
};

//! Scene points measurePrior() measures the start on, at most.
const size_t kPriorPoints = 400;

//! Matches a pair of views contributes to refineEMc() (every n-th by id: a fixed, even sample).
const size_t kRefineMatchesPerPair = 60;

/*
  eMc refined on the pilot's observations at the focal length f: every pair of views sharing 15 ids
  or more, at most kRefineMatchesPerPair of its matches, the epipolar residuals through the robot
  (EpipolarThroughRobot, Cauchy loss of scale 2 px: a few wrong matches and the kinematics' own
  error); Ceres. The measured start's eMc is the start. False (eMc unchanged) when Ceres finds no
  usable solution or too few matches.
*/
bool refineEMc(const std::vector<vpSelfCalibDataset::View> &views, const vpCameraParameters &cam, double f,
               vpSelfCalib::Rigid &eMc)
{
  const double mu = cam.get_py() / cam.get_px();
  const auto ray = [&](const vpImagePoint &p) {
    return Eigen::Vector3d((p.get_u() - cam.get_u0()) / f, (p.get_v() - cam.get_v0()) / (mu * f), 1);
  };
  double w[3] = {0, 0, 0}, dt[3] = {0, 0, 0};
  ceres::Problem problem;
  size_t residuals = 0;
  for (size_t i = 0; i < views.size(); ++i)
    for (size_t k = i + 1; k < views.size(); ++k) {
      std::map<int, vpImagePoint> in_i;
      for (const auto &o : views[i].points)
        in_i[o.id] = o.ip;
      std::vector<std::pair<vpImagePoint, vpImagePoint>> common;
      for (const auto &o : views[k].points)
        if (in_i.count(o.id))
          common.push_back({in_i[o.id], o.ip});
      if (common.size() < 15)
        continue;
      const vpSelfCalib::Rigid A = vpSelfCalib::rigidFromVisp(views[k].fMe.inverse() * views[i].fMe); // e_kMe_i
      const auto pair = std::make_shared<PairEssential>(EpipolarThroughRobot{A.R, eMc.R, A.t, eMc.t});
      const size_t step = std::max<size_t>(1, common.size() / kRefineMatchesPerPair);
      for (size_t c = 0; c < common.size(); c += step) {
        problem.AddResidualBlock(new EpipolarCost(pair, ray(common[c].first), ray(common[c].second), f),
                                 new ceres::CauchyLoss(2.0), w, dt);
        ++residuals;
      }
    }
  if (residuals < 30)
    return false;
  ceres::Solver::Options so;
  so.max_num_iterations = 50;
  so.num_threads = 1; // PairEssential: one thread
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable())
    return false;
  Eigen::Matrix3d dR;
  ceres::AngleAxisToRotationMatrix(w, dR.data());
  eMc.R = eMc.R * dR;
  eMc.t += Eigen::Vector3d(dt[0], dt[1], dt[2]);
  return true;
}
} // namespace

vpFeatureFrontEnd::Prior vpSelfCalibImageCorrespondences::measurePrior(
    const vpKinematicChain &model, const vpSelfCalibDataset &dataset,
    const std::vector<std::vector<vpSelfCalibDataset::Observation>> &pilot, double threshold_px, std::string &how)
{
  if (pilot.size() != dataset.views.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpSelfCalibImageCorrespondences::measurePrior: " + std::to_string(pilot.size()) +
                                   " views of observations for " + std::to_string(dataset.views.size()) + " views");
  // At most kPriorPoints scene points (every n-th id): the start's RANSACs cost with the points, and
  // a few hundred spread over the images measure a start as well as thousands.
  std::set<int> ids;
  for (const auto &view : pilot)
    for (const auto &o : view)
      ids.insert(o.id);
  std::set<int> kept;
  const size_t every = (ids.size() + kPriorPoints - 1) / kPriorPoints;
  size_t n = 0;
  for (int id : ids)
    if (n++ % std::max<size_t>(every, 1) == 0)
      kept.insert(id);
  std::vector<vpSelfCalibDataset::View> views(dataset.views.size());
  for (size_t k = 0; k < views.size(); ++k) {
    const vpSelfCalibDataset::View &v = dataset.views[k];
    if (v.q.size() == model.getNumJoints() && v.q.size() > 0)
      views[k].fMe = model.get_fMe(v.q);
    else if (v.q.size() == 0 && v.has_fMe)
      views[k].fMe = v.fMe;
    else {
      how = "view " + std::to_string(k) + " has neither the model's joints nor an end-effector pose";
      return vpFeatureFrontEnd::Prior();
    }
    views[k].has_fMe = true;
    for (const auto &o : pilot[k])
      if (kept.count(o.id))
        views[k].points.push_back(o);
  }
  // A known focal length: the pixels through the lens; else a pinhole camera's (the start's rule).
  const vpSelfCalib::CameraModel lens = vpSelfCalibPipeline::lensOf(dataset);
  const std::vector<vpSelfCalibDataset::View> pixels =
      dataset.focal_known ? vpSelfCalibPipeline::undistorted(views, lens) : views;
  const vpSelfCalibPipeline::MeasuredStart m =
      vpSelfCalibPipeline::measuredStart(pixels, lens, dataset.width, {}, dataset.focal_known, threshold_px);
  how = m.how;
  if (!m.has_eMc)
    return vpFeatureFrontEnd::Prior();
  vpSelfCalib::Rigid eMc = m.eMc;
  const double f = m.has_fx ? m.fx : dataset.cam.get_px();
  if (refineEMc(pixels, dataset.cam, f, eMc))
    how += "; eMc refined on the epipolar geometry of every pair";
  vpFeatureFrontEnd::Prior prior;
  for (const vpSelfCalibDataset::View &v : views)
    prior.fMc.push_back(v.fMe * vpSelfCalib::toVisp(eMc));
  prior.cam = dataset.cam;
  if (m.has_fx) {
    const double mu = dataset.cam.get_py() / dataset.cam.get_px();
    prior.cam.initPersProjWithoutDistortion(f, mu * f, dataset.cam.get_u0(), dataset.cam.get_v0());
  }
  return prior;
}

namespace
{
/*
  The front end's options with the caller's prior (Options::prior): on a camera on the effector,
  measured from a pilot of the images (measurePrior()), the model's guess when the pilot does not
  measure it (a warning in `notes`); a camera in the world: the guess. `how` gets what made it.
*/
vpFeatureFrontEnd::Options withPrior(const vpSelfCalibImageCorrespondences::Options &options,
                                     const vpSelfCalibDataset &dataset, std::vector<std::string> &notes,
                                     std::string &how)
{
  vpFeatureFrontEnd::Options fo = options.front_end;
  // The yardstick's dots are looked for only when the dataset declares a yardstick: dots found in a
  // scene that has none would be a false yardstick.
  fo.yardstick = fo.yardstick && dataset.yardstick.length > 0;
  if (!options.prior || !fo.prior.empty() || !fo.features || fo.measure_prior)
    return fo;
  const vpFeatureFrontEnd::Prior guess = vpSelfCalibImageCorrespondences::makePrior(*options.prior, dataset);
  if (guess.empty())
    return fo;
  if (dataset.camera_mount != vpSelfCalibDataset::CAMERA_ON_EFFECTOR || !fo.guided) {
    fo.prior.fMc = guess.fMc;
    fo.prior.cam = guess.cam;
    how = "the model's eMc guess and the dataset's camera";
    return fo;
  }
  const vpKinematicChain model = *options.prior;
  const double threshold = std::max(1.0, fo.ransac_threshold);
  fo.measure_prior = [model, dataset, guess, threshold, &notes, &how](
                         const std::vector<std::vector<vpSelfCalibDataset::Observation>> &pilot) {
    std::string start;
    vpFeatureFrontEnd::Prior measured =
        vpSelfCalibImageCorrespondences::measurePrior(model, dataset, pilot, threshold, start);
    if (!measured.empty()) {
      how = "measured from the images: eMc and f from " + start;
      measured.rotation_sd = guess.rotation_sd;
      measured.translation_sd = guess.translation_sd;
      return measured;
    }
    how = "the model's eMc guess and the dataset's camera (" + start + ")";
    notes.push_back("the front end's prior could not be measured from the images (" + start +
                    "): the model's eMc guess and the dataset's focal length guide the matching; if they are far "
                    "off, the probe check may not see it");
    vpFeatureFrontEnd::Prior p = guess;
    return p;
  };
  return fo;
}
// Options that cannot work, refused before any image is read.
void checkOptions(const vpSelfCalibImageCorrespondences::Options &options)
{
  if (options.mask_board) {
    if (!options.board)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpSelfCalibImageCorrespondences: mask_board needs a board to mask");
    if (!options.front_end.features)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpSelfCalibImageCorrespondences: mask_board leaves only natural features, and "
                                 "the front end's features are off");
    if (!(options.mask_margin >= 0 && options.mask_margin < 1e4))
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpSelfCalibImageCorrespondences: mask_margin must be in [0, 1e4) px");
  }
}
} // namespace

vpSelfCalibImageCorrespondences::Result vpSelfCalibImageCorrespondences::fromDatasetImages(vpSelfCalibDataset &dataset,
                                                                                           const Options &options)
{
  checkOptions(options);
  Result result;
  if (needsFrontEnd(dataset)) {
    if (options.board)
      runOnImages(dataset, readImages(dataset), options, result);
    else {
      std::vector<std::string> notes;
      const vpFeatureFrontEnd::Options fo = withPrior(options, dataset, notes, result.prior);
      result.front_end = vpFeatureFrontEnd::fillDataset(dataset, fo);
      result.front_end_ran = true;
      result.warnings.insert(result.warnings.end(), notes.begin(), notes.end());
      result.warnings.insert(result.warnings.end(), result.front_end.warnings.begin(), result.front_end.warnings.end());
    }
  }
  finish(dataset, options, result);
  return result;
}

std::vector<vpImage<unsigned char>> vpSelfCalibImageCorrespondences::readImages(const vpSelfCalibDataset &dataset)
{
  return vpFeatureFrontEnd::readImages(dataset, "vpSelfCalibImageCorrespondences");
}

vpSelfCalibImageCorrespondences::Result
vpSelfCalibImageCorrespondences::fromImages(vpSelfCalibDataset &dataset,
                                            const std::vector<vpImage<unsigned char>> &images, const Options &options)
{
  if (images.size() != dataset.views.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpSelfCalibImageCorrespondences: " + std::to_string(images.size()) + " images for " +
                                   std::to_string(dataset.views.size()) + " views");
  checkOptions(options);
  Result result;
  runOnImages(dataset, images, options, result);
  finish(dataset, options, result);
  return result;
}

void vpSelfCalibImageCorrespondences::runOnImages(vpSelfCalibDataset &dataset,
                                                  const std::vector<vpImage<unsigned char>> &images,
                                                  const Options &options, Result &result)
{
  // The board only masked: found in every image, its region out of the front end's masks.
  std::vector<std::string> notes;
  vpFeatureFrontEnd::Options front_end = withPrior(options, dataset, notes, result.prior);
  front_end.masks = vpFeatureFrontEnd::viewMasks(dataset, front_end.masks, "vpSelfCalibImageCorrespondences");
  if (options.board && options.mask_board) {
    const vpBoardDetector detector(*options.board);
    const std::vector<vpImage<unsigned char>> user = front_end.masks;
    front_end.masks.clear();
    result.board_ran = true;
    for (size_t k = 0; k < images.size(); ++k) {
      result.board.push_back(detector.detect(images[k]));
      const vpBoardDetector::Result &b = result.board.back();
      vpImage<unsigned char> mask = boardMask(b, images[k].getHeight(), images[k].getWidth(), options.mask_margin);
      if (!user.empty()) {
        const vpImage<unsigned char> &u = user[user.size() == 1 ? 0 : std::min(k, user.size() - 1)];
        if (u.getHeight() == mask.getHeight() && u.getWidth() == mask.getWidth())
          for (unsigned int i = 0; i < mask.getSize(); ++i)
            mask.bitmap[i] = u.bitmap[i] ? mask.bitmap[i] : 0;
        else // the front end's own check names the wrong size
          mask = u;
      }
      front_end.masks.push_back(mask);
      if (b.found)
        ++result.board_images;
      else
        result.warnings.push_back("view " + std::to_string(k) +
                                  (dataset.views[k].image.empty() ? std::string() : " (" + dataset.views[k].image + ")") +
                                  ": board not found, so not masked: " + b.message);
    }
  }
  // Without a board the feature front end always runs (and refuses options that find nothing).
  if (!options.board || options.mask_board || options.front_end.features || !options.front_end.dot_grids.empty()) {
    result.front_end = vpFeatureFrontEnd::process(images, front_end);
    result.front_end_ran = true;
    result.warnings.insert(result.warnings.end(), notes.begin(), notes.end());
    result.warnings.insert(result.warnings.end(), result.front_end.warnings.begin(), result.front_end.warnings.end());
    for (size_t k = 0; k < dataset.views.size(); ++k)
      dataset.views[k].points = result.front_end.observations[k];
    dataset.yardstick.id_a = result.front_end.yardstick_a;
    dataset.yardstick.id_b = result.front_end.yardstick_b;
  } else {
    // The board alone: the views' points are the board's, the yardstick's ends are not known yet.
    for (vpSelfCalibDataset::View &v : dataset.views)
      v.points.clear();
    dataset.yardstick.id_a = dataset.yardstick.id_b = -1;
  }
  if (options.board && !options.mask_board)
    addBoard(dataset, images, options, result);
}

vpImage<unsigned char> vpSelfCalibImageCorrespondences::boardMask(const vpBoardDetector::Result &board,
                                                                  unsigned int height, unsigned int width,
                                                                  double margin)
{
  vpImage<unsigned char> mask(height, width, 255);
  if (!board.found || board.corners.empty())
    return mask;
  std::vector<cv::Point> pts, hull;
  for (const auto &o : board.corners)
    pts.emplace_back(static_cast<int>(std::lround(o.ip.get_u())), static_cast<int>(std::lround(o.ip.get_v())));
  cv::convexHull(pts, hull);
  cv::Mat m(static_cast<int>(height), static_cast<int>(width), CV_8UC1, mask.bitmap);
  cv::fillConvexPoly(m, hull, cv::Scalar(0));
  const int thickness = static_cast<int>(std::lround(2 * margin));
  if (thickness > 0)
    cv::polylines(m, hull, true, cv::Scalar(0), thickness);
  return mask;
}

void vpSelfCalibImageCorrespondences::addBoard(vpSelfCalibDataset &dataset,
                                               const std::vector<vpImage<unsigned char>> &images,
                                               const Options &options, Result &result)
{
  const vpBoardDetector detector(*options.board);
  const int first = options.board->id_offset,
            last = first + options.board->numIds() - 1;
  auto collision = [&](const std::string &what) {
    return vpSelfCalibException(vpSelfCalibException::badValue,
                                "vpSelfCalibImageCorrespondences: the board's ids (" + std::to_string(first) + " to " +
                                    std::to_string(last) + ") collide with " + what +
                                    ": choose another board id offset");
  };
  for (const vpFeatureFrontEnd::DotGrid &g : options.front_end.dot_grids)
    if (g.first_id <= last && first < g.first_id + static_cast<int>(g.cols * g.rows))
      throw collision("a dot grid's (from " + std::to_string(g.first_id) + ")");
  for (const vpSelfCalibDataset::View &v : dataset.views)
    for (const vpSelfCalibDataset::Observation &o : v.points)
      if (o.id >= first && o.id <= last)
        throw collision("the front end's point " + std::to_string(o.id));

  result.board_ran = true;
  for (size_t k = 0; k < images.size(); ++k) {
    result.board.push_back(detector.detect(images[k]));
    const vpBoardDetector::Result &b = result.board.back();
    if (b.found) {
      ++result.board_images;
      std::vector<vpSelfCalibDataset::Observation> &points = dataset.views[k].points;
      points.insert(points.end(), b.corners.begin(), b.corners.end());
    } else
      result.warnings.push_back("view " + std::to_string(k) +
                                (dataset.views[k].image.empty() ? std::string() : " (" + dataset.views[k].image + ")") +
                                ": board not found: " + b.message);
  }
  // The yardstick rule (see the class).
  if (!dataset.yardstick.isSet() && result.board_images >= 2) {
    if (dataset.yardstick.length > 0) {
      std::ostringstream w;
      w << "the dataset's yardstick (" << dataset.yardstick.length
        << " m) was not found in the images: the board's first row is the yardstick instead";
      result.warnings.push_back(w.str());
    }
    dataset.yardstick = detector.getYardstick();
    result.board_yardstick = true;
  }
}

void vpSelfCalibImageCorrespondences::finish(vpSelfCalibDataset &dataset, const Options &options, Result &result)
{
  if (result.front_end_ran || result.board_ran) {
    for (bool seen : result.front_end.yardstick_seen)
      result.yardstick_images += seen;
    for (const std::vector<bool> &grid : result.front_end.grid_seen)
      for (bool seen : grid)
        result.grids_found += seen;
    // A view where the front end found nothing (no track, no grid, no yardstick dot, no board) cannot
    // be used.
    std::vector<vpSelfCalibDataset::View> kept;
    for (size_t k = 0; k < dataset.views.size(); ++k) {
      if (dataset.views[k].points.empty()) {
        DroppedView d;
        d.index = static_cast<unsigned int>(k);
        d.image = dataset.views[k].image;
        result.dropped.push_back(d);
      } else
        kept.push_back(std::move(dataset.views[k]));
    }
    dataset.views = std::move(kept);
  }
  if (options.method) {
    result.method = *options.method;
    return;
  }
  result.method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
  for (const vpSelfCalibDataset::View &v : dataset.views)
    if (v.q.size() == 0 && v.has_fMe)
      result.method = vpRobotSelfCalibration::HAND_EYE;
}
