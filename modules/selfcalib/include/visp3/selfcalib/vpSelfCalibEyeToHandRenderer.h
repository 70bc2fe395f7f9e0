/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibEyeToHandRenderer.h
  \brief Rendered images of an eye-to-hand set-up: a camera fixed in the robot's world looking at a
  board carried by the tool, with the tool's own textured parts around it.
*/
#ifndef VP_SELFCALIB_EYE_TO_HAND_RENDERER_H
#define VP_SELFCALIB_EYE_TO_HAND_RENDERER_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <map>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImage.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

/*!
  \class vpSelfCalibEyeToHandRenderer
  \ingroup group_selfcalib_simulation
  \brief Rendered images of an eye-to-hand set-up (dataset camera_mount world): a camera fixed at
  bMc in the robot's base frame sees, at every controller pose bMe, the board of scene CHARUCO or
  APRILTAGS of vpSelfCalibRenderer::Options (the same print as the eye-in-hand board scenes) at
  bMe eMo, and the tool's parts that move with it: a plate on the flange (e's z = 0, 0.24 x 0.18 m,
  ViSP's Klimt photograph) behind the board and the last link, a box of 0.09 x 0.09 m reaching
  0.22 m back along e's -z from the plate (ViSP's Solvay photograph on its sides): texture a
  natural-feature front end would see move with the arm. Everything else is mid-grey. Each pixel
  is the mean of 4 x 4 samples (the board's edges where the truth says), then render() blurs and
  adds noise as vpSelfCalibRenderer does (Options::blur_sd, noise_sd, seed).

  The board's frame o is vpBoardDetector's (x right and y down as printed, z into the board), so
  the layout the detector finds is the truth of its points in o; boardOnTool() places it on the
  tool facing away from the flange.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibEyeToHandRenderer
{
public:
  /*!
    The camera (intrinsics, image size, pose bMc in the base frame) and the board's pose eMo on the
    tool. Throws vpSelfCalibException for a scene other than CHARUCO or APRILTAGS, a board OpenCV
    cannot draw, an empty image size, or a texture that cannot be read (visp-images-data missing).
  */
  vpSelfCalibEyeToHandRenderer(const vpSelfCalibRenderer::Options &options, const vpCameraParameters &cam,
                               unsigned int width, unsigned int height, const vpHomogeneousMatrix &bMc,
                               const vpHomogeneousMatrix &eMo);

  //! The image at the true end-effector pose bMe; view_index selects the noise stream.
  vpImage<unsigned char> render(const vpHomogeneousMatrix &bMe, unsigned int view_index) const;

  /*!
    The board on the tool: its print's centre `offset` m in front of the flange along e's z, its
    z axis (into the board) against e's z (the printed side facing away from the flange), its x
    along e's x, then turned by the theta-u vector (tux, tuy, tuz) about its centre.
  */
  static vpHomogeneousMatrix boardOnTool(const vpSelfCalibRenderer::Options &options, double offset = 0.05,
                                         double tux = 0, double tuy = 0, double tuz = 0);

  /*!
    The eye-to-hand simulation of the rendered set-up (simulate --camera-mount world --images): a
    1280 x 720 camera of f 1000 px, the board within 6 cm of its axis, its outline (getOutline())
    in every image, placed on the tool by boardOnTool(options, 0.05, 0.1, -0.15, 0.3). The caller
    sets the seed, the number of views and the controller poses' error.
  */
  static vpSelfCalibSimulator::EyeToHandOptions simulation(const vpSelfCalibRenderer::Options &options);

  /*!
    The print's four outer corners in the board's frame (ids 0 to 3): what must be in the image for
    the whole board to be (vpSelfCalibSimulator::EyeToHandOptions::layout).
  */
  static std::map<int, vpColVector> getOutline(const vpSelfCalibRenderer::Options &options);

private:
  struct Part {
    vpImage<unsigned char> texture;
    vpColVector corners[4]; //!< in e (the tool's parts) or o (the board)
  };
  vpSelfCalibRenderer::Options m_opt;
  vpCameraParameters m_cam;
  unsigned int m_width, m_height;
  vpHomogeneousMatrix m_cMb, m_eMo;
  std::vector<Part> m_parts; //!< the tool's parts, in e
  Part m_print;              //!< the board, in o
};

#endif
