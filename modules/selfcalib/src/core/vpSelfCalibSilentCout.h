/*
 * ViSP SelfCalib: std::cout silenced around a third-party call that prints (ViSP's camera XML parser,
 * vpSimulatorViper850's constructor): library code never prints, and their text is not the caller's.
 */
#ifndef VP_SELFCALIB_SILENT_COUT_H
#define VP_SELFCALIB_SILENT_COUT_H

#include <iostream>

namespace vpSelfCalib
{
//! std::cout writes nothing while this lives (its buffer is restored, and its state cleared, after).
//! std::cout is the process's: callers serialise the calls they silence.
class SilentCout
{
public:
  SilentCout() : m_saved(std::cout.rdbuf(nullptr)) {}
  ~SilentCout() { std::cout.rdbuf(m_saved); }
  SilentCout(const SilentCout &) = delete;
  SilentCout &operator=(const SilentCout &) = delete;

private:
  std::streambuf *m_saved;
};
} // namespace vpSelfCalib

#endif
