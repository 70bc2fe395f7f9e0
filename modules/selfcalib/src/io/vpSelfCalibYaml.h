/*
 * ViSP SelfCalib: private YAML helpers shared by the file readers and writers (not installed).
 */
#ifndef VP_SELFCALIB_YAML_H
#define VP_SELFCALIB_YAML_H

#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <visp3/core/vpPoseVector.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <yaml-cpp/yaml.h>

#include "../core/vpSelfCalibFiles.h" // writeFileAtomically, for the writers of these files
#include "../core/vpSelfCalibRange.h" // kMaxLength, kMaxAngle, kMaxPixels

namespace vpSelfCalib
{
//! Plausibility limits of the files' numbers (beyond them a value is a mistake, and the solvers overflow).
// kMaxLength (m), kMaxAngle (rad), kMaxPixels (px): vpSelfCalibRange.h, shared with the library's entry points.
constexpr double kMaxImagePixels = 2.5e8; //!< width x height of an image
constexpr size_t kMaxPoses = 100000;      //!< poses in a dataset
constexpr size_t kMaxJoints = 64;         //!< joints of a robot or of a pose
constexpr size_t kMaxObservations = 5000000; //!< observations in a dataset (alias bombs expand to more)
constexpr size_t kMaxFileBytes = size_t(256) << 20; //!< bytes of a YAML file

//! Typed access to YAML nodes; every error names the file kind, the source, the key and what was expected.
class Reader
{
public:
  Reader(const std::string &what, const std::string &source) : m_what(what), m_source(source) {}

  [[noreturn]] void fail(const std::string &key, const std::string &what) const
  {
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               m_what + " " + m_source + ": key '" + key + "': " + what);
  }

  static std::string show(const YAML::Node &n)
  {
    if (!n.IsDefined() || n.IsNull())
      return "nothing";
    if (n.IsScalar())
      return "'" + n.Scalar() + "'";
    return n.IsSequence() ? "a list" : "a map";
  }

  double number(const YAML::Node &n, const std::string &key) const
  {
    if (!n.IsDefined() || n.IsNull())
      fail(key, n.IsDefined() ? "empty; expected a number" : "missing; expected a number");
    if (!n.IsScalar())
      fail(key, "expected a number, got " + show(n));
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception &) {
      fail(key, "expected a number, got " + show(n));
    }
    if (!std::isfinite(v))
      fail(key, "expected a finite number, got " + show(n));
    return v;
  }

  std::string text(const YAML::Node &n, const std::string &key) const
  {
    if (!n.IsDefined() || n.IsNull())
      fail(key, n.IsDefined() ? "empty; expected a string" : "missing; expected a string");
    if (!n.IsScalar())
      fail(key, "expected a string, got " + show(n));
    // yaml-cpp reads any bytes but writes invalid UTF-8 as U+FFFD: such a name or path would not
    // survive a write and read (found by fuzzing), and is a wrong file name anyway.
    if (!validUtf8(n.Scalar()))
      fail(key, "expected UTF-8 text, got invalid bytes");
    // A control character (a line break, a tab, a carriage return left by a Windows editor) in a
    // name or path is a mistake, and yaml-cpp writes some of them back unquoted, so that they would
    // not survive a write and read (found by fuzzing: a path ending in a carriage return).
    for (size_t i = 0; i < n.Scalar().size(); ++i) {
      const unsigned char c = static_cast<unsigned char>(n.Scalar()[i]);
      if (c < 0x20 || c == 0x7F) {
        static const char *hex = "0123456789ABCDEF";
        fail(key, std::string("expected text without control characters, got the control character 0x") + hex[c >> 4] +
                      hex[c & 0xF] + " at position " + std::to_string(i));
      }
    }
    return n.Scalar();
  }

  static bool validUtf8(const std::string &s)
  {
    for (size_t i = 0; i < s.size();) {
      const unsigned char c = static_cast<unsigned char>(s[i]);
      size_t n = 0;
      unsigned int cp = 0;
      if (c < 0x80) {
        ++i;
        continue;
      } else if ((c >> 5) == 0x6) {
        n = 1;
        cp = c & 0x1F;
      } else if ((c >> 4) == 0xE) {
        n = 2;
        cp = c & 0x0F;
      } else if ((c >> 3) == 0x1E) {
        n = 3;
        cp = c & 0x07;
      } else
        return false;
      for (size_t k = 1; k <= n; ++k) {
        if (i + k >= s.size())
          return false;
        const unsigned char d = static_cast<unsigned char>(s[i + k]);
        if ((d >> 6) != 0x2)
          return false;
        cp = (cp << 6) | (d & 0x3F);
      }
      // Overlong forms, surrogates and values above U+10FFFF are not UTF-8.
      if ((n == 1 && cp < 0x80) || (n == 2 && cp < 0x800) || (n == 3 && cp < 0x10000) || cp > 0x10FFFF ||
          (cp >= 0xD800 && cp <= 0xDFFF))
        return false;
      i += n + 1;
    }
    return true;
  }

  vpPoseVector pose(const YAML::Node &n, const std::string &key) const
  {
    if (!n.IsSequence() || n.size() != 6)
      fail(key, "expected a pose vector of 6 numbers [tx, ty, tz, tux, tuy, tuz] (m, rad), got " +
                    (n.IsSequence() ? "a list of " + std::to_string(n.size()) : show(n)));
    vpPoseVector p;
    for (unsigned int i = 0; i < 6; ++i)
      p[i] = number(n[i], key + "[" + std::to_string(i) + "]");
    checkRotation(p, key);
    for (unsigned int i = 0; i < 3; ++i)
      if (!(std::abs(p[i]) <= kMaxLength)) {
        std::ostringstream os;
        os << "a translation of " << p[i] << " m: expected at most " << kMaxLength << " m";
        fail(key + "[" + std::to_string(i) + "]", os.str());
      }
    return p;
  }

  //! A theta-u vector far beyond a turn is a mistake (and loses all precision: 4e307 rad became a
  //! NaN pose on writing, found by fuzzing).
  void checkRotation(const vpPoseVector &p, const std::string &key) const
  {
    const double angle = std::hypot(p[3], p[4], p[5]);
    if (!(angle <= 2 * M_PI + 1e-9)) {
      std::ostringstream os;
      os << "a rotation of |theta u| = " << angle << " rad: expected at most 2 pi";
      fail(key, os.str());
    }
  }

  //! The name of a map key; YAML also allows lists, maps and nulls as keys, which these files never use.
  std::string keyName(const YAML::Node &key, const std::string &where) const
  {
    if (!key.IsScalar())
      fail(where.empty() ? "(map key)" : where + ".(key)", "keys are plain names, got " + show(key));
    return key.Scalar();
  }

  //! A number within [lo, hi]: finite and plausible (1e200 px or a link of 1e308 m are mistakes,
  //! and would overflow the solvers); the message names the key, the range and the unit.
  double bounded(const YAML::Node &n, const std::string &key, double lo, double hi, const char *unit) const
  {
    const double v = number(n, key);
    if (!(v >= lo && v <= hi)) {
      std::ostringstream os;
      os << "expected a value from " << lo << " to " << hi << " " << unit << ", got " << show(n);
      fail(key, os.str());
    }
    return v;
  }

  //! A list of at most `max` entries (an alias-expanded YAML file can hold millions).
  void atMost(const YAML::Node &list, size_t max, const std::string &key, const std::string &what) const
  {
    if (list.size() > max)
      fail(key, std::to_string(list.size()) + " " + what + ": at most " + std::to_string(max) + " are read");
  }

  /*!
    Unknown keys are errors (they are usually typos), and so is a key given twice: YAML forbids
    it, yaml-cpp keeps the first silently, and the file's author may have meant the second.
  */
  void onlyKeys(const YAML::Node &map, const std::set<std::string> &allowed, const std::string &where) const
  {
    std::set<std::string> seen;
    for (const auto &kv : map) {
      const std::string k = keyName(kv.first, where);
      if (!seen.insert(k).second)
        fail(where.empty() ? k : where + "." + k, "given twice (which one is meant?)");
      if (!allowed.count(k)) {
        std::string list;
        for (const std::string &a : allowed)
          list += (list.empty() ? "" : ", ") + a;
        fail(where.empty() ? k : where + "." + k, "unknown key (expected one of: " + list + ")");
      }
    }
  }

private:
  std::string m_what, m_source;
};

//! The whole content of a file, at most kMaxFileBytes counted while reading (readTextFileBounded);
//! throws vpSelfCalibException (ioError) naming `what` (the kind of file) and the file when it
//! cannot be read.
inline std::string readTextFile(const std::string &filename, const std::string &what)
{
  return readTextFileBounded(filename, what, kMaxFileBytes);
}

//! A yaml-cpp error as the module's exception, with the line and column when yaml-cpp knows them.
[[noreturn]] inline void rethrowYaml(const YAML::Exception &e, const std::string &what, const std::string &source,
                                     const std::string &kind)
{
  std::ostringstream os;
  os << what << " " << source << ": " << kind;
  if (!e.mark.is_null())
    os << " at line " << e.mark.line + 1 << ", column " << e.mark.column + 1;
  os << ": " << e.msg;
  throw vpSelfCalibException(vpSelfCalibException::parseError, os.str());
}

//! Parses YAML text; a syntax error names the line and column.
inline YAML::Node loadYamlRoot(const std::string &text, const std::string &what, const std::string &source)
{
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception &e) {
    rethrowYaml(e, what, source, "YAML syntax error");
  }
}

/*!
  Runs a parser over a YAML tree. The parsers check every node they read, so a yaml-cpp exception
  escaping them is a case they missed (found by fuzzing once: a list used as a map key): it still
  becomes a vpSelfCalibException naming the file, never an unknown exception.
*/
template <typename F> auto parseYaml(const std::string &what, const std::string &source, F &&parse)
{
  try {
    return parse();
  } catch (const YAML::Exception &e) {
    rethrowYaml(e, what, source, "unexpected YAML structure");
  }
}

} // namespace vpSelfCalib

#endif
