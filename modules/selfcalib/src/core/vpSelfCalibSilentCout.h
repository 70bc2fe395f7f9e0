/*
 * ViSP SelfCalib: std::cout silenced around a third-party call that prints (ViSP's camera XML parser,
 * vpSimulatorViper850's constructor): library code never prints, and their text is not the caller's.
 */
#ifndef VP_SELFCALIB_SILENT_COUT_H
#define VP_SELFCALIB_SILENT_COUT_H

#include <iostream>
#include <mutex>

namespace vpSelfCalib
{
/*!
  std::cout writes nothing while this lives; its buffer is restored (and its state cleared) after.
  std::cout is the process's, so every SilentCout holds one lock for its lifetime: two silenced
  calls on two threads run one after the other, and neither restores a buffer the other saved. The
  lock is recursive: a SilentCout inside another on the same thread is allowed (the inner one
  restores the silence, the outer one the caller's buffer).
*/
class SilentCout
{
public:
  SilentCout() : m_lock(mutex()), m_saved(std::cout.rdbuf(nullptr)) {}
  ~SilentCout() { std::cout.rdbuf(m_saved); }
  SilentCout(const SilentCout &) = delete;
  SilentCout &operator=(const SilentCout &) = delete;

private:
  //! The one lock of every silenced call of the library.
  static std::recursive_mutex &mutex()
  {
    static std::recursive_mutex m;
    return m;
  }

  std::lock_guard<std::recursive_mutex> m_lock; //!< taken before the buffer is saved, released after it is restored
  std::streambuf *m_saved;
};
} // namespace vpSelfCalib

#endif
