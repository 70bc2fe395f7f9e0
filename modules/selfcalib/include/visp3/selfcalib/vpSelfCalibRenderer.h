/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibRenderer.h
  \brief Rendered images of the reference scenario, seen through the simulator's true robot, for the
  image front end: a non-planar textured scene (two planes meeting at a ridge through the scene
  centre, tilted +-30 degrees towards the home viewpoint, 0.11 x 0.16 m each, textured with ViSP's
  Klimt and Solvay images from visp-images-data) and a yardstick: two dark dots on white square
  patches of 3 cm (a: dot radius 4 mm, b: 6 mm) lying on the first plane, the simulator's
  yardstick length apart.
*/
#ifndef VP_SELFCALIB_RENDERER_H
#define VP_SELFCALIB_RENDERER_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpPoseVector.h>
#include <visp3/core/vpImage.h>
#include <visp3/core/vpImagePoint.h>
#include <visp3/selfcalib/vpDotGrid.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

/*!
  \class vpSelfCalibRenderer
  \ingroup group_selfcalib_simulation
  \brief Rendered images of the reference scenario, seen through the simulator's true robot, for
  the image front end: a non-planar textured scene (two planes meeting at a ridge through the
  scene centre, tilted +-30 degrees towards the home viewpoint, 0.11 x 0.16 m each, textured with
  ViSP's Klimt and Solvay images from visp-images-data) and a yardstick: two dark dots on white
  square patches of 3 cm (a: dot radius 4 mm, b: 6 mm) lying on the first plane, the simulator's
  yardstick length apart. Rendering is ViSP's vpImageSimulator (bilinear), then Gaussian blur and
  Gaussian pixel noise (seeded per view).

  Scene DOTS (the paper's experiment: a dot pattern on a non-planar object): the same two planes
  carry white faces with asymmetric circle grids of dark dots instead of the photographs: 4 x 5
  dots of radius 2.2 mm on the first plane (between the yardstick's patches), 4 x 9 of radius 3.2 mm
  on the second, 1 cm steps. getDotGrids() describes them as the image front end looks for them
  (vpFeatureFrontEnd::Options::dot_grids) and getDotCentres() gives their centres in f.

  Scenes CHARUCO and APRILTAGS (boards with coded markers, for vpBoardDetector): one flat board
  through the scene centre, facing the home viewpoint, its x axis along the home camera's x, drawn
  from OpenCV's own layout and marker bits (CharucoBoard, drawMarker) with a white margin, and
  nothing else (no photographs, no yardstick: the board's first row is the yardstick). CHARUCO:
  Options::charuco_*; APRILTAGS: tags 0, 1, 2, 3 of Options::tag_family, tag_size m each, on a 2 x
  2 grid of tag_spacing (getTagBundle()). getBoardPose() places the board's frame (vpBoardDetector's:
  x right and y down as printed, z into the board) in f: the truth of its points.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibRenderer
{
public:
  enum Scene {
    TEXTURED, //!< photographs on the two planes (natural features)
    DOTS,     //!< asymmetric dot grids on the two planes (dot targets)
    CHARUCO,  //!< a ChArUco board facing the home viewpoint
    APRILTAGS //!< a bundle of four AprilTags facing the home viewpoint
  };

  //! Settings of vpSelfCalibRenderer (the defaults are the member initialisers).
  struct Options {
    Scene scene = TEXTURED;
    std::string texture_dir; //!< empty: visp-images-data's ViSP-images directory
    double blur_sd = 0.7;    //!< px, Gaussian blur of the rendered image (0: none)
    double noise_sd = 2.0;   //!< grey levels, Gaussian noise added after the blur
    uint64_t seed = 1;
    //! Scene CHARUCO: squares (OpenCV's count: cols along x), sides (m), OpenCV dictionary.
    unsigned int charuco_cols = 7, charuco_rows = 5;
    double charuco_square = 0.02, charuco_marker = 0.015;
    std::string charuco_dictionary = "DICT_6X6_250";
    //! Scene APRILTAGS: the family (36h11, 36h10, 25h9, 16h5), the tags' side and their centres' spacing (m).
    std::string tag_family = "36h11";
    double tag_size = 0.04, tag_spacing = 0.06;
    //! Throws vpSelfCalibException for a negative blur or noise, or a board OpenCV cannot draw.
    void check() const;
  };

  //! Keeps a reference to the simulator, which must outlive the renderer. Throws
  //! vpSelfCalibException when a texture cannot be read (visp-images-data missing).
  vpSelfCalibRenderer(const vpSelfCalibSimulator &simulator, const Options &options);

  //! The image of the true camera at joints q; view_index selects the noise stream.
  vpImage<unsigned char> render(const vpColVector &q, unsigned int view_index) const;

  /*!
    The images at every joint vector of qs, image k = render(qs[k], k), rendered on `threads`
    threads (0: the machine's hardware threads); the images do not depend on the thread count.
  */
  std::vector<vpImage<unsigned char>> render(const std::vector<vpColVector> &qs, unsigned int threads = 0) const;

  /*!
    The truth behind a pixel: the scene point (in f) that the true camera at joints q sees at
    pixel ip, the nearest of the rendered quads along its ray (a photograph's plane or a
    yardstick patch). False when the ray meets none. For the front end's tests and benchmark.
  */
  bool surfacePoint(const vpColVector &q, const vpImagePoint &ip, vpColVector &fX) const;

  /*!
    What render() does to the image vpImageSimulator draws, for other rendered scenes (tests of the
    board detector): a Gaussian blur of sd blur_sd px (none when 0), then Gaussian noise of sd
    noise_sd grey levels from random stream `stream` of `seed`, rounded and clipped to 0-255.
  */
  static void blurAndNoise(vpImage<unsigned char> &I, double blur_sd, double noise_sd, uint64_t seed,
                           uint64_t stream);

  //! Scenes CHARUCO and APRILTAGS: the board's frame in f (fMb; see the class).
  const vpHomogeneousMatrix &getBoardPose() const { return m_fMb; }
  //! Scene APRILTAGS: tag id -> its pose in the board's frame (bMt: its centre, no turn).
  static std::map<int, vpPoseVector> getTagBundle(const Options &options);

  //! The yardstick's ends in f (3-vectors) and its length (0 for the board scenes).
  const vpColVector &getYardstickEndA() const { return m_end_a; }
  const vpColVector &getYardstickEndB() const { return m_end_b; }
  double getYardstickLength() const;
  //! Radius of the dots of ends a and b (m).
  static constexpr double kDotRadiusA = 0.004, kDotRadiusB = 0.006;

  //! Scene DOTS: the grids (columns, rows, first point id; empty for TEXTURED) and every dot's
  //! centre in f, by id.
  const std::vector<vpDotGrid> &getDotGrids() const { return m_grids; }
  const std::map<int, vpColVector> &getDotCentres() const { return m_dot_centres; }
  //! First id of the dot grids' points (far above the feature tracks' ids); grid g starts at
  //! kFirstDotId + 1000 g.
  static constexpr int kFirstDotId = vpDotGrid::kDefaultFirstId;

private:
  struct Quad {
    vpImage<unsigned char> texture;
    vpColVector corners[4]; //!< in f: top-left, top-right, bottom-right, bottom-left
  };
  const vpSelfCalibSimulator &m_sim;
  Options m_opt;
  std::vector<Quad> m_quads;
  vpColVector m_end_a, m_end_b;
  std::vector<vpDotGrid> m_grids;
  std::map<int, vpColVector> m_dot_centres;
  vpHomogeneousMatrix m_fMb;
  void addBoard(const vpHomogeneousMatrix &fMc_home, const vpColVector &centre);
};

#endif
