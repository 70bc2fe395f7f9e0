/*
 * ViSP SelfCalib: private (not installed): the coded-marker boards of vpBoardDetector, ChArUco
 * boards and AprilTags (OpenCV aruco): their descriptions' parts, checks, detection and layouts.
 * See vpBoardDetector.h for the conventions (frames, ids).
 */
#ifndef VP_MARKER_BOARDS_H
#define VP_MARKER_BOARDS_H

#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include <visp3/selfcalib/vpBoardDetector.h>

namespace vpMarkerBoards
{
//! Options::check() of CHARUCO and APRILTAG: throws vpSelfCalibException (badValue).
void check(const vpBoardDetector::Options &o);
//! Options::numIds() of CHARUCO and APRILTAG.
int numIds(const vpBoardDetector::Options &o);
//! parse() of the descriptions charuco:..., apriltag:... (parts split at ':') and
//! apriltag-bundle:FILE; `where` starts every message.
vpBoardDetector::Options parse(const std::vector<std::string> &parts, const std::string &where);
//! toString() of CHARUCO and APRILTAG.
std::string toString(const vpBoardDetector::Options &o);
//! detect() of CHARUCO and APRILTAG on a grey image.
vpBoardDetector::Result detect(const cv::Mat &img, const vpBoardDetector::Options &o);
//! getLayout() of CHARUCO and APRILTAG.
std::map<int, vpColVector> layout(const vpBoardDetector::Options &o);
//! getYardstick() of CHARUCO and APRILTAG.
vpSelfCalibDataset::Yardstick yardstick(const vpBoardDetector::Options &o);
} // namespace vpMarkerBoards

#endif
