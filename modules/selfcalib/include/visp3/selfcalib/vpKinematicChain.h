/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpKinematicChain.h
  \brief Serial revolute arm with a wrist camera: nominal model, complete and parametrically continuous
  error model, forward kinematics and identification Jacobian.
*/
#ifndef VP_KINEMATIC_CHAIN_H
#define VP_KINEMATIC_CHAIN_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpMatrix.h>
#include <visp3/core/vpPoseVector.h>

/*!
  \class vpKinematicChain
  \ingroup group_selfcalib_kinematics
  \brief Serial revolute arm with a wrist camera: nominal model, complete and parametrically
  continuous error model, forward kinematics and identification Jacobian.

  <b>Frames.</b> A transform aMb maps coordinates in frame b to coordinates in frame a.
  f is the reference (world) frame, b the robot base, e the end-effector (flange), c the camera.

  <b>Nominal model.</b> One row per revolute joint, standard or modified Denavit-Hartenberg:
  - dh:  A_i = Rz(q_i + theta_offset_i) Tz(d_i) Tx(a_i) Rx(alpha_i)
  - mdh: A_i = Rx(alpha_i) Tx(a_i) Rz(q_i + theta_offset_i) Tz(d_i)  (alpha_i, a_i are those of the
    previous link, as in Craig's table)

  and fMe(q) = fMb A_1 ... A_n nMe, fMc(q) = fMe(q) eMc.

  Both conventions are rewritten as one product of constant placements and pure joint rotations:

      fMc(q) = fMb D_base  prod_i [ P_i D_i Rz(q_i) ]  L  nMe  eMc D_eMc

  where P_i locates the axis of joint i (its z axis) in the frame that follows joint i-1, and L is
  what follows the last joint. For dh, P_1 = I, P_i = Rz(theta_{i-1}) Tz(d_{i-1}) Tx(a_{i-1})
  Rx(alpha_{i-1}) and L = Rz(theta_n) Tz(d_n) Tx(a_n) Rx(alpha_n); for mdh, P_i = Rx(alpha_i) Tx(a_i)
  Rz(theta_i) Tz(d_i) and L = I.

  <b>Error model.</b> Each D is a 6-D correction D(t, r) = [exp([r]x) | t] (translation t in m,
  rotation r as a theta-u vector in rad, ViSP pose-vector order tx ty tz tux tuy tuz). There is one on
  the base (D_base, in the base frame), one on the placement of every joint axis (D_i, in the frame
  of joint i's nominal axis: ji.rx, ji.ry tilt the axis, ji.tx, ji.ty shift it, ji.tz slides along
  it, ji.rz is the joint offset error) and one on the hand-eye transform (D_eMc, in the camera
  frame). Corrections are local exponential coordinates, so the model is parametrically continuous
  whatever the nominal geometry (parallel axes included). It is complete and redundant on purpose:
  6 (n + 2) parameters, of which 4 n + 6 are independent with absolute pose measurements; the
  identification layer picks an independent set.

  Parameters are ordered by block (base, j1, ..., jn, eMc) and inside a block as
  tx ty tz rx ry rz, and named "base.tx", "j3.ry", "eMc.rz"...

  <b>Jacobian.</b> getJacobian() returns the 6 x (6(n+2)) derivative of the camera pose with
  respect to the corrections: rows 0-2 the camera position in f, rows 3-5 the small rotation
  dphi in f such that fRc(p + dp) = exp([dphi]x) fRc(p). It is analytic and exact at any parameter
  value, not only at zero.
*/
class VISP_SELFCALIB_EXPORT vpKinematicChain
{
public:
  enum Convention { DH, MDH };

  //! One revolute joint: a nominal DH or MDH row and its limits.
  struct Joint {
    double a = 0, d = 0, alpha = 0, theta_offset = 0; //!< m, m, rad, rad
    double min = -M_PI, max = M_PI;                   //!< joint limits, rad
  };

  //! Number of correction components per block (tx ty tz rx ry rz).
  static constexpr unsigned int kBlockSize = 6;

  vpKinematicChain();
  //! Throws vpSelfCalibException on an empty joint list, non-finite values or min > max.
  vpKinematicChain(const std::string &name, Convention convention, const std::vector<Joint> &joints,
                   const vpPoseVector &fMb = vpPoseVector(), const vpPoseVector &nMe = vpPoseVector(),
                   const vpPoseVector &eMc = vpPoseVector());

  /*!
    A named preset: "puma560" (Corke's standard-DH table, see doc/formats.md) or "viper850" (nominal
    values read at run time from ViSP's vpViper850 with its default PTGrey Flea2 camera tool, so that
    get_fMc() equals vpViper850::get_fMc()). Throws vpSelfCalibException on an unknown name.
  */
  static vpKinematicChain preset(const std::string &name);
  static std::vector<std::string> presetNames();

  /*!
    Robot-model YAML (see doc/formats.md): either a file with convention, joints, base, flange, eMc and
    optional corrections, or a preset name as value of "preset" (corrections may follow).
    Every malformed or inconsistent input throws vpSelfCalibException naming the file, the key and
    what was expected.
  */
  static vpKinematicChain loadYaml(const std::string &filename);
  static vpKinematicChain fromYamlString(const std::string &yaml, const std::string &source = "<string>");
  //! A model name that is a preset loads the preset, anything else is read as a YAML file.
  static vpKinematicChain fromPresetOrFile(const std::string &name_or_file);
  //! Writes the full model (nominal rows, frames, non-zero corrections) with 17 significant digits,
  //! so that loadYaml() reproduces fMc exactly.
  void saveYaml(const std::string &filename) const;
  std::string toYamlString() const;

  // Description
  const std::string &getName() const { return m_name; }
  void setName(const std::string &name) { m_name = name; }
  Convention getConvention() const { return m_convention; }
  unsigned int getNumJoints() const { return static_cast<unsigned int>(m_joints.size()); }
  const std::vector<Joint> &getJoints() const { return m_joints; }
  vpColVector getJointMin() const;
  vpColVector getJointMax() const;
  void setJointLimits(const vpColVector &qmin, const vpColVector &qmax);
  //! True when every joint value is finite and inside its limits (with a tolerance in rad).
  bool isInJointLimits(const vpColVector &q, double tolerance = 0.0) const;

  //! Nominal frames. They are stored as pose vectors (the file representation), so that a model
  //! written and read back gives bit-identical transforms.
  vpHomogeneousMatrix get_fMb() const { return vpHomogeneousMatrix(m_fMb); }
  vpHomogeneousMatrix get_nMe() const { return vpHomogeneousMatrix(m_nMe); }
  //! Nominal hand-eye transform (without its correction).
  vpHomogeneousMatrix get_eMc() const { return vpHomogeneousMatrix(m_eMc); }
  const vpPoseVector &get_fMb_pose() const { return m_fMb; }
  const vpPoseVector &get_nMe_pose() const { return m_nMe; }
  const vpPoseVector &get_eMc_pose() const { return m_eMc; }
  void set_fMb(const vpPoseVector &fMb) { m_fMb = fMb; }
  void set_nMe(const vpPoseVector &nMe) { m_nMe = nMe; }
  void set_eMc(const vpPoseVector &eMc) { m_eMc = eMc; }
  /*!
    The camera fixed in the world (eye-to-hand): the hand-eye slot (get_eMc(), its eMc.*
    corrections, get_eMc_corrected()) then holds the camera in the base frame, bMc, and the model
    file says so (`camera_mount: world`, the key `bMc` in place of `eMc`). False: the camera on the
    end-effector, the slot is eMc (the default).
  */
  bool isCameraInWorld() const { return m_camera_in_world; }
  void setCameraInWorld(bool in_world) { m_camera_in_world = in_world; }

  // Error-model parameters
  unsigned int getNumParameters() const { return kBlockSize * (getNumJoints() + 2); }
  std::vector<std::string> getParameterNames() const;
  //! Index of a parameter by name ("j2.tx"); throws on an unknown name.
  unsigned int getParameterIndex(const std::string &name) const;
  const vpColVector &getParameters() const { return m_params; }
  void setParameters(const vpColVector &p);
  double getParameter(const std::string &name) const;
  void setParameter(const std::string &name, double value);
  //! Sets every correction to zero: the chain becomes its nominal model.
  void resetParameters();
  //! The same robot with all corrections at zero.
  vpKinematicChain nominal() const;

  // Forward kinematics (corrections included)
  vpHomogeneousMatrix get_fMe(const vpColVector &q) const;
  vpHomogeneousMatrix get_fMc(const vpColVector &q) const;
  //! Effective hand-eye transform eMc D_eMc.
  vpHomogeneousMatrix get_eMc_corrected() const;
  /*!
    The chain as constant placements between joint rotations, corrections included:
    fMc(q) = M_0 Rz(q_1) M_1 Rz(q_2) ... M_{n-1} Rz(q_n) M_n get_eMc_corrected(), with
    M_0 = fMb D_base P_1 D_1, M_i = P_{i+1} D_{i+1} and M_n = L nMe (the flange in the frame of the
    last joint). Returns M_0 .. M_n: the joint origins of a URDF, for example.
  */
  std::vector<vpHomogeneousMatrix> getPlacements() const;

  /*!
    Identification Jacobian of the camera pose with respect to the corrections at joint vector q
    (6 x getNumParameters(); see the class description for the row convention).
  */
  vpMatrix getJacobian(const vpColVector &q) const;
  /*!
    Joint Jacobian of the camera pose (6 x n): rows 0-2 the velocity of the camera origin in f,
    rows 3-5 the angular velocity in f, for unit joint velocities.
  */
  vpMatrix getJointJacobian(const vpColVector &q) const;

  /*!
    One 6-D correction as a homogeneous matrix: [exp([r]x) | t] with v = (tx ty tz rx ry rz).
  */
  static vpHomogeneousMatrix correction(const double *v);

private:
  struct Frames; // forward pass results
  void buildPlacements();
  void checkJoints(const vpColVector &q, const char *where) const;
  void forward(const vpColVector &q, Frames &out, bool keep_prefixes) const;

  std::string m_name;
  Convention m_convention;
  std::vector<Joint> m_joints;
  vpPoseVector m_fMb, m_nMe, m_eMc;
  bool m_camera_in_world = false;
  std::vector<vpHomogeneousMatrix> m_P; // P_i, i = 0..n-1 (placement of joint i+1's axis)
  vpHomogeneousMatrix m_L;              // after the last joint
  vpColVector m_params;
};

#endif
