/*
 * visp-selfcalib simulate: the pieces its files share (simulateCommand.cpp: the command line and the
 * reference scenario's dataset and truth; simulateImages.cpp: rendered images in a directory of
 * their own; simulateEyeToHand.cpp: the camera fixed in the world).
 */
#ifndef VISP_SELFCALIB_SIMULATE_H
#define VISP_SELFCALIB_SIMULATE_H

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <visp3/core/vpImage.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "commands.h"

//! The renderer's options of simulate --target.
vpSelfCalibRenderer::Options rendererOptions(const SimulateArgs &a);
//! simulate --target apriltags: the bundle's description (tags.yaml) in `dir`.
void writeTagBundle(const std::filesystem::path &dir, const vpSelfCalibRenderer::Options &ro);
//! The image directories to remove once the new dataset at `out` is in place (simulateImages.cpp).
std::vector<std::string> earlierImageDirectories(const std::string &out);
//! Writes image k = render(k) of every view as a set beside the dataset; returned with its lock.
std::unique_ptr<vpSelfCalibOutputDirectory>
writeImages(const std::function<vpImage<unsigned char>(unsigned int)> &render, const std::string &out,
            vpSelfCalibDataset &ds);
//! The rendered images of the reference scenario's views at joints qs (see writeImages()).
std::unique_ptr<vpSelfCalibOutputDirectory> renderImages(const vpSelfCalibSimulator &sim, const SimulateArgs &a,
                                                         const std::vector<vpColVector> &qs, const std::string &out,
                                                         vpSelfCalibDataset &ds);
//! simulate --camera-mount world --images: a board on the tool rendered by a fixed camera.
int simulateEyeToHandImages(const SimulateArgs &a);
//! simulate --camera-mount world: points data of a board on the tool seen by a fixed camera, and its truth.
int simulateEyeToHand(const SimulateArgs &a);

#endif
