/*
 * ViSP SelfCalib: what the command lines of the tool, the tutorial and the benchmarks share on top
 * of CLI11 (not installed): option value checks with clear messages, and one way to end on --help
 * (exit 0) or a usage error (exit 2).
 */
#ifndef SELFCALIB_CLI_H
#define SELFCALIB_CLI_H

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace selfcalibCli
{
//! The exit code of a usage error (unknown option, missing or wrong value), in every program.
constexpr int kUsageError = 2;

/*!
  A whole number in decimal digits, from `min` to `max`. CLI11 alone reads integers with strtoull
  in base 0: "010" would be 8, "0x10" 16, and "-1" a huge unsigned 64-bit number; and a count
  without an upper bound (--poses 4000000000) runs until killed.
*/
inline CLI::Validator wholeNumber(unsigned long long min = 0,
                                  unsigned long long max = std::numeric_limits<unsigned long long>::max())
{
  return CLI::Validator(
      [min, max](std::string &value) -> std::string {
        const bool bounded = max != std::numeric_limits<unsigned long long>::max();
        const std::string expected =
            "expected a whole number" +
            (bounded ? " from " + std::to_string(min) + " to " + std::to_string(max)
                     : (min > 0 ? " of at least " + std::to_string(min) : std::string())) +
            ", got '" + value + "'";
        if (value.empty() || value.find_first_not_of("0123456789") != std::string::npos)
          return expected;
        errno = 0;
        const unsigned long long v = std::strtoull(value.c_str(), nullptr, 10);
        if (errno == ERANGE || v < min || v > max)
          return expected;
        return std::string();
      },
      std::string());
}

/*!
  0 (the feature off) or a whole number from `min` to `max`, in decimal digits (as wholeNumber()):
  for counts where the values between 0 and min mean nothing (--folds 1).
*/
inline CLI::Validator zeroOrWholeNumber(unsigned long long min, unsigned long long max)
{
  return CLI::Validator(
      [min, max](std::string &value) -> std::string {
        const std::string expected = "expected 0 or a whole number from " + std::to_string(min) + " to " +
                                     std::to_string(max) + ", got '" + value + "'";
        if (value.empty() || value.find_first_not_of("0123456789") != std::string::npos)
          return expected;
        errno = 0;
        const unsigned long long v = std::strtoull(value.c_str(), nullptr, 10);
        if (errno == ERANGE || (v != 0 && (v < min || v > max)))
          return expected;
        return std::string();
      },
      std::string());
}

//! A finite number, at least `min` (or above it when `strict`), and at most `max`.
inline CLI::Validator number(double min = -std::numeric_limits<double>::infinity(), bool strict = false,
                             double max = std::numeric_limits<double>::infinity())
{
  return CLI::Validator(
      [min, strict, max](std::string &value) -> std::string {
        std::ostringstream expected;
        expected << "expected a number";
        if (std::isfinite(min))
          expected << (strict ? " above " : " of at least ") << min;
        if (std::isfinite(max))
          expected << (std::isfinite(min) ? " and" : "") << " at most " << max;
        expected << ", got '" << value << "'";
        char *end = nullptr;
        const double v = std::strtod(value.c_str(), &end);
        if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(v) || v < min ||
            (strict && v == min) || v > max)
          return expected.str();
        return std::string();
      },
      std::string());
}

//! The word `word`, or a number as number(min, strict, max) checks it (its message).
inline CLI::Validator wordOrNumber(const std::string &word, double min, bool strict, double max)
{
  const CLI::Validator n = number(min, strict, max);
  return CLI::Validator(
      [word, n](std::string &value) -> std::string {
        if (value == word)
          return std::string();
        std::string v = value;
        const std::string err = n(v);
        return err.empty() ? err : "expected '" + word + "' or a" + err.substr(std::string("expected a").size());
      },
      std::string());
}

/*!
  Parses the command line. Returns -1 when the program is to go on; otherwise its exit code: 0
  after printing the help (--help), kUsageError after printing a usage error on stderr.
*/
inline int parse(CLI::App &app, int argc, char **argv)
{
  try {
    app.parse(argc, argv);
    return -1;
  } catch (const CLI::Success &e) { // --help
    return app.exit(e);
  } catch (const CLI::ParseError &e) {
    std::string help = app.get_name() + " --help";
    for (const CLI::App *sub : app.get_subcommands())
      help = app.get_name() + " " + sub->get_name() + " --help";
    std::cerr << "error: " << e.what() << "\n'" << help << "' lists the options.\n";
    return kUsageError;
  }
}

//! The benchmarks' common options: --seeds N (seeds 1..N, at least 1).
inline void addSeeds(CLI::App &app, unsigned int &seeds)
{
  app.add_option("--seeds", seeds, "seeds 1..N (default " + std::to_string(seeds) + ")")
      ->type_name("N")
      ->check(wholeNumber(1));
}

//! --noise A,B: pixel noise levels (px), at least 0, or above 0 when strictly_positive.
inline void addNoiseLevels(CLI::App &app, std::vector<double> &noises, const std::string &help,
                           bool strictly_positive = false)
{
  app.add_option("--noise", noises, help)->type_name("A,B")->delimiter(',')->check(number(0, strictly_positive));
}

//! --robots A,B: robot presets among the given names.
inline void addRobots(CLI::App &app, std::vector<std::string> &robots, const std::vector<std::string> &presets)
{
  app.add_option("--robots", robots, "puma560, viper850 (default both)")
      ->type_name("A,B")
      ->delimiter(',')
      ->check(CLI::IsMember(presets));
}
} // namespace selfcalibCli

#endif
