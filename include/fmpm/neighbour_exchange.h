// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_neighbour_exchange_h
#define fmpm_neighbour_exchange_h

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <algorithm>
#include <climits>
#include <map>
#include <type_traits>
#include <vector>

namespace fmpm
{
  using namespace dealii;

  /**
   * MPI tags of fmpm's own point-to-point messages. They lie above deal.II
   * 9.4's tags (300-760, <deal.II/base/mpi_tags.h>) and p4est's (from 214),
   * and below Epetra's (24050-24099).
   */
  namespace MPITags
  {
    /** PointSort::sort(): the points that change rank. */
    constexpr int point_exchange = 1100;
    /** Contact::Manager::gather_point_clouds(): points to the node owners. */
    constexpr int contact_point_clouds = 1101;
  } // namespace MPITags

  /**
   * @brief A some-to-some exchange between known neighbours, without a
   * collective: each rank sends one message, possibly empty, to every rank
   * in @p send_to and receives one from every rank in @p receive_from.
   * Each rank must be in the @p receive_from of every rank in its
   * @p send_to (and only of those), and every key of @p sent must be in
   * @p send_to. Then the result equals deal.II's
   * Utilities::MPI::some_to_some(comm, sent) up to empty vectors: by
   * sending rank, the data received from it (ranks that sent nothing are
   * left out), in ascending rank order. Unlike some_to_some(), it has no
   * barrier, reduction or consensus step; all ranks of @p comm need not
   * call it, only each pair of neighbours together.
   *
   * @tparam T a trivially copyable type (sent as bytes)
   */
  template <typename T>
  std::map<unsigned int, std::vector<T>>
  neighbour_exchange(const MPI_Comm                               &comm,
                     const std::vector<unsigned int>              &send_to,
                     const std::vector<unsigned int>              &receive_from,
                     const std::map<unsigned int, std::vector<T>> &sent,
                     const int                                     tag)
  {
    static_assert(std::is_trivially_copyable<T>::value,
                  "neighbour_exchange() sends T as bytes");
    std::map<unsigned int, std::vector<T>> received;
#ifdef DEAL_II_WITH_MPI
    for (const auto &[rank, data] : sent)
      {
        (void)data;
        Assert(std::find(send_to.begin(), send_to.end(), rank) != send_to.end(),
               ExcMessage("neighbour_exchange(): data for a rank that is not "
                          "a neighbour"));
      }
    std::vector<MPI_Request> requests(send_to.size());
    for (unsigned int i = 0; i < send_to.size(); ++i)
      {
        const auto  it    = sent.find(send_to[i]);
        const void *data  = nullptr;
        std::size_t bytes = 0;
        if (it != sent.end())
          {
            data  = it->second.data();
            bytes = it->second.size() * sizeof(T);
          }
        AssertThrow(bytes <= static_cast<std::size_t>(INT_MAX),
                    ExcMessage("neighbour_exchange(): message over 2 GB"));
        const int ierr = MPI_Isend(data,
                                   static_cast<int>(bytes),
                                   MPI_BYTE,
                                   send_to[i],
                                   tag,
                                   comm,
                                   &requests[i]);
        AssertThrowMPI(ierr);
      }
    // The map orders the ranks, whatever the order of receipt.
    for (const unsigned int rank : receive_from)
      {
        MPI_Status status;
        int        ierr = MPI_Probe(rank, tag, comm, &status);
        AssertThrowMPI(ierr);
        int bytes = 0;
        ierr      = MPI_Get_count(&status, MPI_BYTE, &bytes);
        AssertThrowMPI(ierr);
        Assert(bytes % sizeof(T) == 0, ExcInternalError());
        void *data = nullptr;
        if (bytes > 0)
          {
            std::vector<T> &buffer = received[rank];
            buffer.resize(bytes / sizeof(T));
            data = buffer.data();
          }
        ierr =
          MPI_Recv(data, bytes, MPI_BYTE, rank, tag, comm, MPI_STATUS_IGNORE);
        AssertThrowMPI(ierr);
      }
    const int ierr =
      MPI_Waitall(requests.size(), requests.data(), MPI_STATUSES_IGNORE);
    AssertThrowMPI(ierr);
#else
    (void)comm;
    (void)send_to;
    (void)receive_from;
    (void)sent;
    (void)tag;
#endif
    return received;
  }
} // namespace fmpm

#endif
