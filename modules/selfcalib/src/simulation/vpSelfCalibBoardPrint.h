/*
 * ViSP SelfCalib: private pieces of the renderers (not installed), shared by the eye-in-hand scenes
 * (vpSelfCalibRenderer) and the eye-to-hand one (vpSelfCalibEyeToHandRenderer): a board's printed
 * side as a texture, and one textured quad set up for vpImageSimulator from the side the camera sees.
 */
#ifndef VP_SELFCALIB_BOARD_PRINT_H
#define VP_SELFCALIB_BOARD_PRINT_H

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImage.h>
#include <visp3/robot/vpImageSimulator.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

namespace vpSelfCalib
{
/*!
  The printed side of the board of scene CHARUCO or APRILTAGS (options.charuco_* or tag_*), drawn
  from OpenCV's layout and bits with a white margin: its texture and the quad's corners (x0, y0)
  and (x1, y1) in the board's frame (vpBoardDetector's: x right, y down as printed, z into the
  board), and the print's centre (cx, cy) in that frame.
*/
struct BoardPrint {
  vpImage<unsigned char> texture;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double cx = 0, cy = 0;
};
BoardPrint boardPrint(const vpSelfCalibRenderer::Options &options);

/*!
  A quad of `texture` with corners X (in a frame a: top-left, top-right, bottom-right,
  bottom-left) seen by a camera at cMa: vpImageSimulator draws a quad from the side its corner
  order makes the front only, so the corners are swapped left-right (the texture mirrored) when
  the camera is on the other side.
*/
vpImageSimulator quadSimulator(const vpImage<unsigned char> &texture, const vpColVector X[4],
                               const vpHomogeneousMatrix &cMa);
} // namespace vpSelfCalib

#endif
