// The archives checkpoints are written to and read from (boost's binary archives), declared for the components' save() and load().
#ifndef dieflow_archive_h
#define dieflow_archive_h

namespace boost
{
  namespace archive
  {
    class binary_oarchive;
    class binary_iarchive;
  } // namespace archive
} // namespace boost

namespace dieflow
{
  using OutputArchive = boost::archive::binary_oarchive;
  using InputArchive  = boost::archive::binary_iarchive;
} // namespace dieflow

#endif
