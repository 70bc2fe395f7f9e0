/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*
  The board tests' check of a refused board description: vpBoardDetector::parse throws, and its
  message holds `message`.
*/
#ifndef VP_SELFCALIB_BOARD_SPEC_TEST_H
#define VP_SELFCALIB_BOARD_SPEC_TEST_H

#include <gtest/gtest.h>

#include <string>

#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

inline void expectParseError(const std::string &spec, const std::string &message)
{
  try {
    vpBoardDetector::parse(spec);
    ADD_FAILURE() << "'" << spec << "' was accepted";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find(message), std::string::npos)
        << "'" << spec << "': " << e.getStringMessage() << " (expected '" << message << "')";
  }
}

#endif
