/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibProtocol.h
  \brief The protocol of a calibration run: calibrate, cross-validate, verify on held-out data, judge.
*/
#ifndef VP_SELFCALIB_PROTOCOL_H
#define VP_SELFCALIB_PROTOCOL_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <functional>
#include <optional>
#include <string>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibCrossValidation.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpSelfCalibProtocol
  \ingroup group_selfcalib_protocol
  \brief The protocol of a calibration run (doc/concepts.md, "The protocol"): by default every view calibrates
  and a k-fold cross-validation (vpSelfCalibCrossValidation) measures the model on views it was not
  calibrated on; Options::calibration or Options::holdout keep the paper's split, the last views
  verifying; Options::heldout verifies the model on a second dataset.

  plan() checks the options against the dataset's number of views and reads the held-out dataset;
  run() calibrates (vpRobotSelfCalibration), cross-validates, verifies on the held-out dataset and
  judges the run (judge()). Progress, notes and warnings go to a callback; nothing is printed. The
  messages of the exceptions name the options as the command line spells them (--calibration,
  --holdout, --folds, --heldout).
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibProtocol
{
public:
  //! Settings of vpSelfCalibProtocol (the defaults are the member initialisers).
  struct Options {
    unsigned int calibration = 0; //!< the first N views calibrate, the others verify (0: see holdout)
    unsigned int holdout = 0;     //!< the last N views verify (0: none, unless calibration is set)
    unsigned int folds = 5;       //!< k-fold cross-validation (0: none)
    bool folds_given = false;     //!< folds was asked for (else its default applies only without a split)
    std::string heldout;          //!< a second dataset to verify on (empty: none)
    /*!
      Prepares the held-out dataset's observations before it is verified (the image front end on
      its images, with the calibration's options); empty: its views are used as they are.
    */
    std::function<void(vpSelfCalibDataset &)> held_out_front_end;
  };
  //! The split of the views and the folds, as plan() decided them.
  struct Plan {
    unsigned int calibration = 0, held_out = 0; //!< views calibrating, views after them verifying
    unsigned int folds = 0;                     //!< 0: no cross-validation
    std::string note;                           //!< why there is no cross-validation, when it was not asked for
    std::string heldout_file;                   //!< Options::heldout
    vpSelfCalibDataset heldout;                 //!< its dataset (views empty without)
  };
  //! What a run leads to.
  struct Result {
    Plan plan;
    vpRobotSelfCalibration::Options options; //!< those the calibration ran with (num_calibration_poses from the plan)
    vpRobotSelfCalibration::Result run;      //!< the calibration itself, before the protocol's verdicts
    vpRobotSelfCalibration::Result calibration; //!< the calibration with the protocol's verdicts (judge())
    std::optional<vpSelfCalibCrossValidation::Result> cv;
    std::optional<vpSelfCalibCrossValidation::HeldOut> verified;
    //! The calibration gave a model (status OK or DOUBTFUL); else cv and verified are empty.
    bool calibrated() const;
  };
  //! What a message to the callback is.
  enum EventKind {
    NOTE,     //!< a choice of the protocol the user did not ask for
    PROGRESS, //!< the stage that starts
    WARNING   //!< something the user should look at; the run goes on
  };
  using Callback = std::function<void(EventKind, const std::string &)>;

  /*!
    The split of the `num_views` views and the folds from the options, and the held-out dataset
    read. Throws vpSelfCalibException when the options contradict each other or the dataset.
  */
  static Plan plan(const Options &options, unsigned int num_views);
  /*!
    Calibrates `dataset` from `nominal` with `options` (its num_calibration_poses set from the plan),
    then, when that gives a model, the cross-validation over the calibration views, the
    verification on the held-out dataset and the verdicts (judge()).
  */
  static Result run(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset,
                    const vpRobotSelfCalibration::Options &options, const Plan &plan,
                    const Options &protocol_options, const Callback &callback = Callback());
  /*!
    The cross-validation's word on the model, into `calibration`'s findings (severity DOUBT), status
    (DOUBTFUL) and message: when the calibrated model predicts the held-out views worse than the
    nominal model in most folds and by 5 % or more on average, the calibration does not generalise
    (too many parameters for the views, or a wrong input); the same when most folds fail: the
    calibration does not survive leaving a few views out.
  */
  static void judge(const vpSelfCalibCrossValidation::Result &cv, vpRobotSelfCalibration::Result &calibration);
};

#endif
