/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibExport.h
  \brief VISP_SELFCALIB_EXPORT, the symbol-visibility macro on the module's public classes (ViSP's
  VISP_EXPORT convention): dllexport / dllimport on Windows when the library is shared, default
  visibility elsewhere.
*/
#ifndef VP_SELFCALIB_EXPORT_H
#define VP_SELFCALIB_EXPORT_H

#if defined(_WIN32) || defined(__CYGWIN__)
#if defined(VISP_SELFCALIB_BUILDING_SHARED)
#define VISP_SELFCALIB_EXPORT __declspec(dllexport)
#elif defined(VISP_SELFCALIB_SHARED)
#define VISP_SELFCALIB_EXPORT __declspec(dllimport)
#else
#define VISP_SELFCALIB_EXPORT
#endif
#else
#define VISP_SELFCALIB_EXPORT __attribute__((visibility("default")))
#endif

#endif
