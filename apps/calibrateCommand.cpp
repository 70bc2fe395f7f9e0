/*
 * visp-selfcalib calibrate: the front end, the protocol (vpSelfCalibProtocol), the result files
 * (vpSelfCalibResultsFile, vpSelfCalibReport) and the summary.
 */
#include "calibrate.h"

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <set>

#include <opencv2/core.hpp>

#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpModelExport.h>
#include <visp3/selfcalib/vpSelfCalibPoseStudy.h>
#include <visp3/selfcalib/vpSelfCalibReport.h>
#include <visp3/selfcalib/vpSelfCalibResultsFile.h>

namespace fs = std::filesystem;

namespace
{
//! The image front end on the dataset's images (when it has no points), its figures on stderr.
vpSelfCalibImageCorrespondences::Result runFrontEnd(vpSelfCalibDataset &ds,
                                                    const vpSelfCalibImageCorrespondences::Options &co,
                                                    bool board_geometry)
{
  const size_t num_images = ds.views.size();
  if (vpSelfCalibImageCorrespondences::needsFrontEnd(ds))
    std::cerr << "... image front end (" << num_images << " images)\n";
  else if (co.board && board_geometry)
    std::cerr << "... --board: the dataset's views come with their points, the board's by their ids: its layout "
                 "is their prior (--board-geometry)\n";
  else if (co.board)
    std::cerr << "warning: --board: the dataset's views come with their points; the board is not looked for\n";
  const vpSelfCalibImageCorrespondences::Result cr = vpSelfCalibImageCorrespondences::fromDatasetImages(ds, co);
  if (cr.front_end_ran) {
    if (!co.front_end.dot_grids.empty())
      std::cerr << "... dot grids found " << cr.grids_found << " times in " << num_images << " images\n";
    std::cerr << "... " << cr.front_end.num_tracks << " tracks, yardstick in " << cr.yardstick_images << " images, "
              << std::setprecision(2) << cr.front_end.seconds << " s\n";
  }
  if (cr.board_ran) {
    std::cerr << "... board " << vpBoardDetector::toString(*co.board) << " found in " << cr.board_images << " of "
              << num_images << " images\n";
    if (cr.board_yardstick)
      std::cerr << "... yardstick: the ends of the board's first row (ids " << ds.yardstick.id_a << ", "
                << ds.yardstick.id_b << "), " << std::setprecision(6) << ds.yardstick.length << " m\n";
  }
  for (const std::string &w : cr.warnings)
    std::cerr << "warning: " << w << "\n";
  if (cr.front_end_ran || cr.board_ran) {
    for (auto d = cr.dropped.rbegin(); d != cr.dropped.rend(); ++d)
      std::cerr << "warning: view " << d->index << " (" << d->image << "): no correspondence found; left out\n";
  }
  // Too few views left: said here with the front end's part (the calibration would say "the
  // dataset has N views", N the views kept, not the dataset's). A board in no image is the run's
  // own error (named with what the detector saw).
  const bool board_unseen = cr.board_ran && !co.mask_board && cr.board_images == 0 && !cr.board.empty();
  if (!cr.dropped.empty() && ds.views.size() < 3 && num_images >= 3 && !board_unseen)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "the image front end found correspondences in " + std::to_string(ds.views.size()) +
                                   " of the " + std::to_string(num_images) +
                                   " images (the others are left out, above): at least 3 calibration views are "
                                   "needed; " +
                                   (co.mask_board ? "--mask-board hides the board, and the rest of the images "
                                                    "matches too little: calibrate without --mask-board"
                                                  : "check the images (texture, overlap between views) and the board's "
                                                    "description"));
  return cr;
}

//! The protocol's options from the command line; the held-out dataset's front end runs as the dataset's.
vpSelfCalibProtocol::Options protocolOptions(const CalibrateArgs &a, const vpSelfCalibImageCorrespondences::Options &co)
{
  vpSelfCalibProtocol::Options p;
  p.calibration = a.calibration;
  p.holdout = a.holdout;
  p.folds = a.folds;
  p.folds_given = a.folds_given;
  p.heldout = a.heldout;
  const int threads = a.threads;
  p.held_out_front_end = [co, threads](vpSelfCalibDataset &held) {
    if (vpSelfCalibImageCorrespondences::needsFrontEnd(held)) {
      std::cerr << "... image front end of the held-out dataset (" << held.views.size() << " images)\n";
      cv::setNumThreads(threads);
      vpSelfCalibImageCorrespondences::fromDatasetImages(held, co);
      cv::setNumThreads(1);
    }
  };
  return p;
}

//! The protocol's notes, progress and warnings on stderr.
void printEvent(vpSelfCalibProtocol::EventKind kind, const std::string &message)
{
  std::cerr << (kind == vpSelfCalibProtocol::NOTE ? "note: " : kind == vpSelfCalibProtocol::WARNING ? "warning: " : "... ")
            << message << "\n";
}

/*!
  The result set in the output directory's staging place: model.yaml, model.urdf, camera.xml,
  results.yaml and the report; returns the report's message.
*/
std::string writeResults(const fs::path &stage, const std::string &dataset, const vpKinematicChain &nominal,
                         const vpSelfCalibDataset &ds, const vpSelfCalibImageCorrespondences::Result &cr,
                         const vpSelfCalibProtocol::Result &p, size_t &report_warnings)
{
  const vpRobotSelfCalibration::Result &r = p.calibration;
  // A doubtful model is written all the same, marked so (its name, results.yaml's status, the report).
  const bool doubtful = r.status == vpRobotSelfCalibration::DOUBTFUL;
  vpKinematicChain model = r.calibrated;
  model.setName(nominal.getName() + (doubtful ? "-calibrated-DOUBTFUL" : "-calibrated"));
  model.setCameraInWorld(r.has_bMc); // eye-to-hand: the file holds bMc, and says so
  model.saveYaml((stage / "model.yaml").string());
  if (r.has_bMc) { // eye-to-hand: the camera a link of the world, the target on the flange
    const vpHomogeneousMatrix bMc(r.bMc), eMo(r.eMo);
    vpModelExport::saveURDF(model, (stage / "model.urdf").string(), &bMc, r.has_eMo ? &eMo : nullptr);
  } else
    vpModelExport::saveURDF(model, (stage / "model.urdf").string());
  vpSelfCalibFileWriter::writeCameraXml((stage / "camera.xml").string(), r.camera, "Camera", ds.width, ds.height,
                                        "self-calibrated by visp-selfcalib");
  vpSelfCalibResultsFile::write((stage / "results.yaml").string(),
                                vpSelfCalibResultsFile::fromRun(r, nominal, dataset, p));
  std::cerr << "... report\n";
  const vpSelfCalibPoseStudy::Result study = // Figure 6
      vpSelfCalibPoseStudy::run(nominal, ds, p.options, vpSelfCalibPoseStudy::Options(), {}, &p.run);
  vpSelfCalibReport::Record run(nominal, ds, p);
  run.front_end = cr.front_end_ran ? &cr.front_end : nullptr;
  run.errors_vs_poses = &study;
  const vpSelfCalibReport::Result report = vpSelfCalibReport::write((stage / "report").string(), run, {});
  for (const std::string &w : report.warnings)
    std::cerr << "warning: " << w << "\n";
  report_warnings = report.warnings.size();
  return report.message;
}
} // namespace

int calibrate(const CalibrateArgs &a)
{
  const std::string &dataset = a.dataset, &out = a.out;
  vpSelfCalibImageCorrespondences::Options co = frontEndOptions(a);
  vpRobotSelfCalibration::Options po = calibrationOptions(a, co);
  const bool pose_auto = std::count(a.pose_sd.begin(), a.pose_sd.end(), "auto") > 0;
  // The image front end runs on `threads` OpenCV threads: its results do not depend on them (test
  // app-deterministic). Everything after it runs on one thread, OpenMP included (OpenCV's
  // setNumThreads sets OpenMP's count, which CHOLMOD/SPQR in the covariance use, and their sums
  // change with it); Ceres's multi-threaded Schur elimination also sums in a scheduling-dependent
  // order. The result files must be bit-reproducible.
  cv::setNumThreads(a.threads);
  vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(dataset);
  if (a.joint_sd.size() == 1 && a.joint_sd[0] == 0)
    ds.joint_sd.clear(); // --joint-sd 0: exact readings, whatever the dataset's robot_error says
  const bool world = ds.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD;
  if (world && !a.method.empty() && co.method == vpRobotSelfCalibration::PAPER)
    throw CLI::ValidationError("--method", "camera_mount: world is calibrated with --method bundle or hand-eye; the "
                                           "paper method measures the camera's motion between views of a scene fixed "
                                           "in the base frame, and the dataset " +
                                               dataset + " says the camera is fixed in the world");
  if (!a.method.empty() && co.method == vpRobotSelfCalibration::PAPER && (!a.joint_sd.empty() || !a.pose_sd.empty()))
    throw CLI::ValidationError(a.joint_sd.empty() ? "--pose-sd" : "--joint-sd",
                               "the paper method models no robot error (its poses come from the images alone): the "
                               "robot's error is modelled by --method bundle (--joint-sd, --pose-sd T,R) or hand-eye "
                               "(--pose-sd)");
  const bool world_bundle = world && !a.method.empty() && co.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
  for (size_t k = 0; world_bundle && k < ds.views.size(); ++k)
    if (ds.views[k].q.size() == 0)
      throw CLI::ValidationError("--method", "camera_mount: world with --method bundle calibrates the arm's kinematics "
                                             "from joint readings; pose " +
                                                 std::to_string(k) + " of " + dataset +
                                                 " has none (a controller pose only): use --method hand-eye");
  if (!world_bundle && (world || co.method == vpRobotSelfCalibration::HAND_EYE))
    refuseBundleOptions(a); // before the front end runs, when the method is known
  const vpKinematicChain nominal = vpKinematicChain::fromPresetOrFile(ds.robot);
  co.prior = nominal; // the front end's prior: the nominal kinematics with eMc and f measured from the images
  const bool hand_eye = world ? !world_bundle : co.method == vpRobotSelfCalibration::HAND_EYE;
  checkParameterLists(nominal, ds, po, hand_eye,
                      !a.estimate.empty() || (po.focal_mode == vpRobotSelfCalibration::FOCAL_AUTO ? !ds.focal_known
                                                                                        : po.focal_mode != vpRobotSelfCalibration::FOCAL_KNOWN));
  if (a.board_geometry && !vpSelfCalibImageCorrespondences::needsFrontEnd(ds) &&
      boardPointsObserved(po.bundle.known_points, ds) < 3)
    throw CLI::ValidationError(
        "--board-geometry", "the dataset's views come with their points, and " +
                                std::to_string(boardPointsObserved(po.bundle.known_points, ds)) + " of the board's " +
                                std::to_string(po.bundle.known_points.size()) +
                                " point ids are among them (3 are needed): the points are not the board's (its layout "
                                "applies to the ids the board detector gives, as in a dataset of images or simulate "
                                "--camera-mount world); leave --board-geometry out, or give the board these points are");
  // Outputs: a set written in a private directory beside --out, moved into place at once, under
  // a lock on --out; never over an input, never over files that are not an earlier run's results.
  vpSelfCalibOutputDirectory outdir(out);
  if (const int refused = checkOutputDirectory(outdir, out, calibrationInputs(dataset, ds), a.force))
    return refused;
  if (const int refused = checkHeldout(dataset, ds, a.heldout))
    return refused;
  if (const int refused = checkControllerPoses(dataset, ds))
    return refused;
  if (const int refused = checkYardstick(dataset, ds, nominal))
    return refused;
  const vpSelfCalibImageCorrespondences::Result cr = runFrontEnd(ds, co, a.board_geometry);
  cv::setNumThreads(1);
  if (cr.board_ran && !co.mask_board && cr.board_images == 0 && !cr.board.empty()) {
    // The board asked for is in no image: named, with what the detector saw in the first one.
    std::cerr << "error: no view shows the board " << vpBoardDetector::toString(*co.board) << " (view 0: "
              << cr.board.front().message << "); check the board's description (type, size, dictionary or tag family)\n";
    return 3;
  }
  // A camera in the world: hand-eye unless the bundle method is asked for (with joint readings).
  po.method = world ? (world_bundle ? vpRobotSelfCalibration::BUNDLE_ADJUSTMENT : vpRobotSelfCalibration::HAND_EYE)
                    : cr.method;
  if (const int refused = checkMethodData(po.method, ds))
    return refused;
  noteRobotModel(ds, po.method);
  if (pose_auto && po.method != vpRobotSelfCalibration::HAND_EYE)
    std::cerr << "warning: --pose-sd auto measures the controller poses' error (hand-eye); the method is "
              << vpRobotSelfCalibration::methodName(po.method) << ", so it is not used\n";
  if (po.method == vpRobotSelfCalibration::HAND_EYE)
    refuseBundleOptions(a);
  stateRobotError(a, po);
  if (po.trust_robot && po.method == vpRobotSelfCalibration::HAND_EYE && ds.pose_sd_translation > 0) {
    // --pose-sd 0 states exact poses: it overrides the dataset's robot_error, as --pose-sd T,R does.
    std::cerr << "... robot error: --pose-sd 0: the controller poses are taken as exact (the dataset's robot_error "
              << ds.pose_sd_translation << " m / " << ds.pose_sd_rotation << " rad is not used)\n";
    ds.pose_sd_translation = ds.pose_sd_rotation = 0;
  }
  const vpSelfCalibProtocol::Options protocol_options = protocolOptions(a, co);
  const vpSelfCalibProtocol::Plan plan =
      vpSelfCalibProtocol::plan(protocol_options, static_cast<unsigned int>(ds.views.size()));
  vpSelfCalibProtocol::Result p =
      vpSelfCalibProtocol::run(nominal, ds, po, plan, protocol_options, printEvent);
  if (!p.calibrated()) {
    std::cerr << (p.run.status == vpRobotSelfCalibration::DEGENERATE_DATA ? "calibration refused: "
                                                                          : "calibration failed: ")
              << vpRobotSelfCalibration::statusName(p.run.status) << ": " << p.run.message
              << "\n";
    noteYardstickLength(ds, nominal, p.run.findings);
    if (cr.front_end_ran && !co.board)
      std::cerr << "note: the correspondences are the images' natural features (no --board); if the images show a "
                   "calibration board or a tag, give it: --board SPEC (import names the board it found; calibrate "
                   "--help lists the types)\n";
    printStatus(p.run, false);
    return 3;
  }
  leadWithFixedParameters(p.calibration);
  const vpRobotSelfCalibration::Result &r = p.calibration;
  for (const auto &f : r.findings)
    std::cerr << vpSelfCalibDataCheck::severityName(f.severity) << ": " << f.message << "\n";
  if (r.status == vpRobotSelfCalibration::DOUBTFUL ||
      std::any_of(r.findings.begin(), r.findings.end(),
                  [](const vpSelfCalibDataCheck::Finding &f) { return f.code == "yardstick-unused"; }))
    noteYardstickLength(ds, nominal, r.findings);
  if (r.status == vpRobotSelfCalibration::DOUBTFUL && a.board_geometry &&
      std::any_of(r.findings.begin(), r.findings.end(), [](const vpSelfCalibDataCheck::Finding &f) {
        return f.code == "residuals-too-large";
      }))
    std::cerr << "note: with --board-geometry the board's layout is part of the model: a board described with its "
              << "rows and columns swapped, or another board's description, leaves such residuals: check --board "
              << a.board << "\n";
  size_t report_warnings = 0;
  const std::string report = writeResults(outdir.staging(), dataset, nominal, ds, cr, p, report_warnings);
  outdir.commit();

  const std::string files[4] = {(fs::path(out) / "model.yaml").string(), (fs::path(out) / "camera.xml").string(),
                                (fs::path(out) / "results.yaml").string(), (fs::path(out) / "model.urdf").string()};
  printSummary(r, p.options.num_calibration_poses);
  std::cout << "\n";
  if (r.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT)
    printAddPoses(r, dataset);
  printProtocol(p);
  std::cout << "wrote " << files[0] << ", " << files[1] << ", " << files[2] << ", " << files[3] << "\n";
  std::cout << "report: " << (fs::path(out) / "report").string() << "/report.md (" << report << ")\n";
  printStatus(r, true, report_warnings);
  if (r.status == vpRobotSelfCalibration::DOUBTFUL) {
    std::cerr << "calibration doubtful: the model is written (marked so) but failed the checks above; "
                 "see results.yaml's findings of severity doubt\n";
    return 3;
  }
  return 0;
}
