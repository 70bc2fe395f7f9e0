/*
 * visp-selfcalib simulate: the rendered images of a run, in a directory of their own beside the
 * dataset, and the clean-up of earlier runs' images (see simulate.h).
 */
#include "simulate.h"

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>

#include <visp3/selfcalib/vpSelfCalibFileWriter.h>

namespace fs = std::filesystem;

namespace
{
//! 8 hex digits, new in every run (the name of a run's image directory).
std::string runName()
{
  std::random_device rd;
  std::ostringstream os;
  os << std::hex << std::setw(8) << std::setfill('0') << (rd() & 0xffffffffu);
  return os.str();
}

//! Whether `name` is STEM-images-XXXXXXXX (8 lower-case hex digits): a run's image directory.
bool isRunImageDirectory(const std::string &name, const std::string &stem)
{
  const std::string prefix = stem + "-images-";
  if (name.size() != prefix.size() + 8 || name.compare(0, prefix.size(), prefix) != 0)
    return false;
  return std::all_of(name.begin() + static_cast<long>(prefix.size()), name.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || (c >= 'a' && c <= 'f'); });
}

//! Whether `dir` holds only rendered images (NNNN.png files), as a run's image directory does.
bool holdsOnlyRenderedImages(const fs::path &dir)
{
  std::error_code ec;
  for (const fs::directory_entry &e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    if (e.is_symlink(ec) || !e.is_regular_file(ec) || n.size() != 8 || n.compare(4, 4, ".png") != 0 ||
        !std::all_of(n.begin(), n.begin() + 4, [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
      return false;
  }
  return !ec;
}

/*
  Removes the image directories beside the dataset at `out` that no dataset points at: a run killed
  between its images' commit and its dataset's rename leaves one. Only those named like a run's
  (STEM-images-XXXXXXXX) that hold rendered images only, not the one `keep` names, and not one a
  live run holds (its lock is taken first).
*/
void removeOrphanImageDirectories(const fs::path &parent, const std::string &stem, const std::string &keep)
{
  std::error_code ec;
  std::vector<fs::path> orphans;
  for (const fs::directory_entry &e : fs::directory_iterator(parent, ec))
    if (isRunImageDirectory(e.path().filename().string(), stem) && e.path().string() != keep &&
        e.is_directory(ec) && !e.is_symlink(ec) && holdsOnlyRenderedImages(e.path()))
      orphans.push_back(e.path());
  for (const fs::path &d : orphans)
    try {
      const vpSelfCalibOutputDirectory held(d.string()); // refused while a live run holds it
      fs::remove_all(d, ec);
    } catch (const vpException &) {
      // a live run's
    }
}
} // namespace

/*
  The image directories to remove once the new dataset is in place: the one of the dataset at
  `out` that an earlier simulate --images wrote (one of ours, beside it, every image in it). Also
  removes what killed runs left: their hidden staging directories (each opened as an output set,
  which removes the leftovers of its name unless a live run holds it) and, when the dataset at
  `out` is absent or one of ours, the image directories no dataset points at.
*/
std::vector<std::string> earlierImageDirectories(const std::string &out)
{
  const fs::path parent = fs::absolute(out).lexically_normal().parent_path();
  const std::string stem = fs::path(out).stem().string();
  std::error_code ec;
  for (const fs::directory_entry &e : fs::directory_iterator(parent, ec)) {
    const std::string n = e.path().filename().string();
    const size_t tmp = n.find(".tmp-");
    if (n.size() > 1 && n[0] == '.' && tmp != std::string::npos && isRunImageDirectory(n.substr(1, tmp - 1), stem))
      try {
        const vpSelfCalibOutputDirectory leftovers((parent / n.substr(1, tmp - 1)).string());
      } catch (const vpException &) {
        // a live run's, or not ours to remove
      }
  }
  if (canonical(out).empty()) {
    removeOrphanImageDirectories(parent, stem, "");
    return {};
  }
  std::string dir;
  try {
    for (const vpSelfCalibDataset::View &v : vpSelfCalibDataset::loadYaml(out).views) {
      const fs::path d = fs::absolute(v.image).lexically_normal().parent_path();
      if (v.image.empty() || d.parent_path() != parent || !isRunImageDirectory(d.filename().string(), stem) ||
          (!dir.empty() && dir != d.string()))
        return {};
      dir = d.string();
    }
  } catch (const vpException &) {
    return {}; // not a dataset: its images, if any, are not ours to remove
  }
  removeOrphanImageDirectories(parent, stem, dir);
  if (dir.empty())
    return {};
  return {dir};
}

//! simulate --target apriltags: the bundle's description (vpBoardDetector's apriltag-bundle file) beside the dataset.
void writeTagBundle(const fs::path &dir, const vpSelfCalibRenderer::Options &ro)
{
  std::ostringstream yaml;
  yaml << "family: " << ro.tag_family << "\ntags:\n";
  for (const auto &t : vpSelfCalibRenderer::getTagBundle(ro))
    yaml << "  - {id: " << t.first << ", size: " << ro.tag_size << ", pose: [" << t.second[0] << ", " << t.second[1]
         << ", 0, 0, 0, 0]}\n";
  const std::string file = ((dir.empty() ? fs::path(".") : dir) / "tags.yaml").string();
  vpSelfCalibFileWriter::write(file, yaml.str(), "tag bundle");
}

//! The renderer's options of simulate --target.
vpSelfCalibRenderer::Options rendererOptions(const SimulateArgs &a)
{
  vpSelfCalibRenderer::Options ro;
  ro.seed = a.so.seed;
  ro.scene = a.target == "dots"        ? vpSelfCalibRenderer::DOTS
             : a.target == "charuco"   ? vpSelfCalibRenderer::CHARUCO
             : a.target == "apriltags" ? vpSelfCalibRenderer::APRILTAGS
                                       : vpSelfCalibRenderer::TEXTURED;
  return ro;
}

/*
  Writes image k = render(k) of every view into a directory of this run's own beside the dataset
  (STEM-images-XXXXXXXX), written as a set (vpSelfCalibOutputDirectory: staged, then renamed into
  place) before the dataset that points at them: a run killed at any moment leaves the earlier
  dataset with its own images (and, killed between the two, an image directory no dataset points
  at, which the next run removes). The set is returned with its lock, to be released once the
  dataset is in place.
*/
std::unique_ptr<vpSelfCalibOutputDirectory>
writeImages(const std::function<vpImage<unsigned char>(unsigned int)> &render, const std::string &out,
            vpSelfCalibDataset &ds)
{
  const fs::path parent = fs::path(out).parent_path(); // as given: the dataset then holds relative paths
  const fs::path img_dir = (parent.empty() ? fs::path(".") : parent) / (fs::path(out).stem().string() + "-images-" + runName());
  auto owned = std::make_unique<vpSelfCalibOutputDirectory>(img_dir.string());
  vpSelfCalibOutputDirectory &set = *owned;
  const bool tty = ::isatty(STDERR_FILENO) != 0; // progress on a terminal only
  for (size_t k = 0; k < ds.views.size(); ++k) {
    std::ostringstream name;
    name << std::setw(4) << std::setfill('0') << k + 1 << ".png";
    // Encoded in memory and written atomically, every write checked (a full disk is an error
    // naming the file and the reason, and the dataset that would point at it is not written).
    try {
      vpSelfCalibFileWriter::writeImage((fs::path(set.staging()) / name.str()).string(),
                                        render(static_cast<unsigned int>(k)));
    } catch (...) {
      if (tty)
        std::cerr << "\n"; // after the progress line
      throw;
    }
    ds.views[k].image = (img_dir / name.str()).string();
    ds.views[k].points.clear();
    if (tty)
      std::cerr << "\r\033[Krendered " << k + 1 << "/" << ds.views.size() << std::flush;
  }
  if (tty)
    std::cerr << "\n";
  set.commit();
  return owned; // its lock held until the dataset points at it: no other run takes it for an orphan
}

//! The rendered images of the reference scenario's views at joints qs (see writeImages()).
std::unique_ptr<vpSelfCalibOutputDirectory> renderImages(const vpSelfCalibSimulator &sim, const SimulateArgs &a, const std::vector<vpColVector> &qs,
                  const std::string &out, vpSelfCalibDataset &ds)
{
  const vpSelfCalibRenderer::Options ro = rendererOptions(a);
  const vpSelfCalibRenderer renderer(sim, ro);
  if (ro.scene == vpSelfCalibRenderer::APRILTAGS)
    writeTagBundle(fs::path(out).parent_path(), ro);
  auto images = writeImages([&](unsigned int k) { return renderer.render(qs[k], k); }, out, ds);
  ds.yardstick.length = renderer.getYardstickLength(); // 0 for the boards: their first row is the yardstick
  ds.yardstick.id_a = ds.yardstick.id_b = -1;
  return images;
}
