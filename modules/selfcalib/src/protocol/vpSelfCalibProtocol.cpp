/*
 * ViSP SelfCalib: the protocol of a calibration run (split, cross-validation, held-out dataset, verdicts).
 */
#include <visp3/selfcalib/vpSelfCalibProtocol.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace
{
//! A DOUBT finding of the protocol: into the findings, the status DOUBTFUL, the message.
void addDoubt(vpRobotSelfCalibration::Result &r, const std::string &code, const std::string &message)
{
  vpSelfCalibDataCheck::Finding f;
  f.severity = vpSelfCalibDataCheck::DOUBT;
  f.code = code;
  f.message = message;
  r.findings.push_back(f);
  r.status = vpRobotSelfCalibration::DOUBTFUL;
  r.message += "; doubtful: " + message;
}

bool gaveModel(vpRobotSelfCalibration::Status s)
{
  return s == vpRobotSelfCalibration::OK || s == vpRobotSelfCalibration::DOUBTFUL;
}

vpSelfCalibException usage(const std::string &message)
{
  return vpSelfCalibException(vpSelfCalibException::badValue, message);
}

//! The split's checks: --calibration, --holdout and the views.
void checkSplit(const vpSelfCalibProtocol::Options &a, unsigned int m)
{
  if (a.calibration > m) {
    std::ostringstream os;
    os << "--calibration " << a.calibration << ": the dataset has " << m
       << " views (the calibration uses the first N, the others verify)";
    throw usage(os.str());
  }
  if (a.holdout && a.calibration && a.calibration + a.holdout != m) {
    std::ostringstream os;
    os << "--calibration " << a.calibration << " and --holdout " << a.holdout << " disagree: the dataset has " << m
       << " views, not " << a.calibration + a.holdout << "; give one of them";
    throw usage(os.str());
  }
  if (a.holdout && (a.holdout >= m || m - a.holdout < 3)) {
    std::ostringstream os;
    os << "--holdout " << a.holdout << ": the dataset has " << m << " views; at least 3 must remain to calibrate";
    throw usage(os.str());
  }
}
} // namespace

bool vpSelfCalibProtocol::Result::calibrated() const { return gaveModel(run.status); }

vpSelfCalibProtocol::Plan vpSelfCalibProtocol::plan(const Options &a, unsigned int m)
{
  checkSplit(a, m);
  Plan p;
  const bool split = a.calibration || a.holdout;
  p.calibration = a.calibration ? a.calibration : m - a.holdout;
  p.held_out = m - p.calibration;
  // Cross-validation: by default when every view calibrates, over the calibration views otherwise.
  p.folds = split && !a.folds_given ? 0 : a.folds;
  if (p.folds && !a.folds_given && p.calibration < 6) {
    p.note = "cross-validation skipped: " + std::to_string(p.calibration) +
             " views, fewer than 6 (each fold would calibrate on 4 views or fewer); --folds K asks for it";
    p.folds = 0;
  }
  if (p.folds) {
    try {
      vpSelfCalibCrossValidation::folds(p.calibration, p.folds);
    } catch (const vpSelfCalibException &e) {
      throw usage("--folds " + std::to_string(p.folds) + ": " + e.getStringMessage());
    }
  }
  if (!a.heldout.empty()) {
    p.heldout_file = a.heldout;
    p.heldout = vpSelfCalibDataset::loadYaml(a.heldout);
    if (p.heldout.views.size() < 2)
      throw usage("--heldout " + a.heldout + ": " + std::to_string(p.heldout.views.size()) +
                  " view(s); at least 2 are needed to verify on");
  }
  return p;
}

vpSelfCalibProtocol::Result vpSelfCalibProtocol::run(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds,
                                                     const vpRobotSelfCalibration::Options &options, const Plan &plan,
                                                     const Options &protocol_options, const Callback &callback)
{
  auto tell = [&callback](EventKind kind, const std::string &message) {
    if (callback)
      callback(kind, message);
  };
  auto stage = [&tell](const std::string &s, unsigned int, unsigned int) { tell(PROGRESS, s); };
  Result p;
  p.plan = plan;
  p.options = options;
  p.options.num_calibration_poses = std::max(3u, plan.calibration);
  p.run = vpRobotSelfCalibration::run(nominal, ds, p.options, stage);
  if (!p.calibrated()) {
    p.calibration = p.run;
    return p;
  }
  if (!plan.note.empty())
    tell(NOTE, plan.note);
  if (plan.folds) {
    vpSelfCalibDataset cal = ds;
    cal.views.resize(plan.calibration);
    vpSelfCalibCrossValidation::Options cvo;
    cvo.folds = plan.folds;
    p.cv = vpSelfCalibCrossValidation::run(nominal, cal, p.options, cvo, p.run, stage); // folds from p.run
    for (size_t f = 0; f < p.cv->fold.size(); ++f)
      if (!gaveModel(p.cv->fold[f].status))
        tell(WARNING, "cross-validation fold " + std::to_string(f + 1) + " failed: " +
                          vpRobotSelfCalibration::statusName(p.cv->fold[f].status) + ": " + p.cv->fold[f].message);
  }
  if (!plan.heldout_file.empty()) {
    vpSelfCalibDataset held = plan.heldout;
    if (held.robot != ds.robot || held.width != ds.width || held.height != ds.height) {
      std::ostringstream os;
      os << "--heldout " << plan.heldout_file << ": its robot (" << held.robot << ") or image size (" << held.width
         << " x " << held.height << ") is not the dataset's (" << ds.robot << ", " << ds.width << " x " << ds.height
         << "): the verification assumes the same robot and camera";
      tell(WARNING, os.str());
    }
    if (protocol_options.held_out_front_end)
      protocol_options.held_out_front_end(held);
    p.plan.heldout = held;
    p.verified = vpSelfCalibCrossValidation::verifyHeldOut(nominal, ds, p.options, p.run, held);
  }
  p.calibration = p.run;
  if (p.cv)
    judge(*p.cv, p.calibration);
  return p;
}

void vpSelfCalibProtocol::judge(const vpSelfCalibCrossValidation::Result &cv, vpRobotSelfCalibration::Result &r)
{
  // Most folds failed: the calibration stands only on all the views together, and a few views less
  // (one fold) lose it; the answer depends on which views are used.
  unsigned int failed = 0;
  for (const auto &f : cv.fold)
    failed += !gaveModel(f.status);
  if (cv.fold.size() >= 2 && 2 * failed > cv.fold.size() && gaveModel(r.status)) {
    std::ostringstream os;
    os << failed << " of " << cv.fold.size()
       << " cross-validation folds failed (each leaves out a few views): the calibration stands only on all the "
          "views together and depends on which views are used; add views, or check the correspondences";
    addDoubt(r, "cross-validation-folds-failed", os.str());
  }
  if (cv.num_ok < 2)
    return;
  unsigned int worse = 0, compared = 0;
  for (const auto &f : cv.fold)
    if (f.calibrated.observations > 0 && f.nominal.observations > 0) {
      ++compared;
      worse += f.calibrated.rms > f.nominal.rms;
    }
  if (2 * worse <= compared || !(cv.calibrated_rms.mean > 1.05 * cv.nominal_rms.mean))
    return;
  std::ostringstream os;
  os << std::setprecision(3) << "the cross-validation's calibrated models predict the held-out views worse than the "
     << "nominal model (reprojection RMS " << cv.calibrated_rms.mean << " px against " << cv.nominal_rms.mean
     << " px; worse in " << worse << " of " << compared
     << " folds): the calibration does not generalise; add views or estimate fewer parameters";
  addDoubt(r, "cross-validation-worse-than-nominal", os.str());
}
