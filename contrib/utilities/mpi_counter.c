// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// mpi_counter: a PMPI interposition library that counts the messages and
// bytes each MPI rank sends, by kind and by the fmpm function that caused
// them. Build and preload it (contrib/utilities/mpi_volumes.sh does this):
//
//   mpicc -shared -fPIC -O2 -o libmpi_counter.so mpi_counter.c -ldl
//   mpirun -np 4 -x LD_PRELOAD=$PWD/libmpi_counter.so
//          -x MPI_COUNTER_DIR=$PWD/counts program ...
//
// At MPI_Finalize every rank writes one line of JSON to
// $MPI_COUNTER_DIR/rank-<rank>.json (nothing if the variable is unset):
//
//   {"rank": r, "size": P,
//    "counts": [[context, kind, messages, bytes], ...],
//    "tags": [[tag, messages, bytes], ...],
//    "peers": {kind: number of distinct destination ranks, ...}}
//
// Kinds. Point-to-point sends (counted at the sender, bytes = count times
// the type size) are classified by their tag; the numbers are those of
// deal.II 9.4's <deal.II/base/mpi_tags.h> (enum starting at 300) and of
// Trilinos' Epetra_MpiCommData.h:
//   p2p:particles      329-331  particle_handler_send_recv_particles_*
//   p2p:some-to-some   300-301  Utilities::MPI::some_to_some() (fmpm's
//                               point exchange and contact before 2026-11-26)
//   p2p:ghost          336-748  partitioner_import/export_*, noncontiguous
//                               partitioner: ghost values and compress() of
//                               LinearAlgebra::distributed::Vector
//   p2p:dealii-other   302-760  the other deal.II tags (consensus
//                               algorithms, ...)
//   p2p:fmpm-points    1100     fmpm's point exchange after the re-bin
//                               (include/fmpm/neighbour_exchange.h)
//   p2p:fmpm-contact   1101     fmpm's contact point clouds
//   p2p:epetra         24050-24099  Epetra import/export (Trilinos matrices)
//   p2p:other          everything else (p4est, Open MPI-internal, ...)
// Collectives are classified by call ("coll:MPI_Allreduce", ...); one call
// is one message, its bytes the payload of this rank: count times type size
// for reductions and broadcasts, the send buffer for gathers, the sum over
// destinations for all-to-all. Collectives on a communicator of one rank
// (e.g. deal.II's Timer on MPI_COMM_SELF) go to "self:MPI_..." kinds.
// Persistent sends (MPI_*send_init) count at MPI_Start/MPI_Startall,
// one-sided MPI_Put/Get/Accumulate by their origin buffer ("rma:...").
//
// Contexts. If MPI_COUNTER_FRAME_PREFIXES is set (comma-separated prefixes
// of mangled symbol names, e.g. "_ZN4fmpm,_ZNK4fmpm"), every call walks its
// stack and names the innermost two frames whose exported symbol matches
// ("inner<-outer", mangled; frames of local symbols are skipped because
// dladdr cannot name them). Otherwise, and when nothing matches, the
// context is "-". Demangle with c++filt.
//
// The counters cover the whole run (set-up included); to get per-step
// figures, run the same scene with two step counts and subtract.

#define _GNU_SOURCE
#include <dlfcn.h>
#include <execinfo.h>
#include <link.h>
#include <mpi.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_KINDS 96
#define MAX_CONTEXTS 2048
#define MAX_TAGS 32768
#define ADDRESS_CACHE 65536
#define MAX_FRAMES 64
#define MAX_PERSISTENT 4096

typedef struct
{
  uint64_t messages, bytes;
} Counter;

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

static const char *kind_names[MAX_KINDS];
static int         n_kinds = 0;

static char    *context_names[MAX_CONTEXTS];
static int      n_contexts = 0;
static Counter *counters; // [MAX_CONTEXTS][MAX_KINDS]
static Counter  tags[MAX_TAGS + 1]; // the last one: tags >= MAX_TAGS
// Destinations of point-to-point sends per kind (rank in the communicator
// of the send; fmpm's communicators are duplicates of MPI_COMM_WORLD).
#define MAX_PEERS 4096
static uint64_t peers[MAX_KINDS][MAX_PEERS / 64];

// Frame prefixes from MPI_COUNTER_FRAME_PREFIXES.
static char *prefixes[16];
static int   n_prefixes = -1; // -1: not read yet

// Return address -> 1 + index into symbol_names (0: empty slot), or -1 if the
// frame does not match.
static struct
{
  void *address;
  int   symbol;
} address_cache[ADDRESS_CACHE];
static char *symbol_names[MAX_CONTEXTS];
static int   n_symbols = 0;

static struct
{
  MPI_Request request;
  int         context, kind;
  uint64_t    bytes;
} persistent[MAX_PERSISTENT];

static int
kind_index(const char *name)
{
  // Names are string literals, so pointers identify them; compare strings
  // anyway (a literal may be duplicated across translation units).
  for (int k = 0; k < n_kinds; ++k)
    if (kind_names[k] == name || strcmp(kind_names[k], name) == 0)
      return k;
  if (n_kinds == MAX_KINDS)
    return MAX_KINDS - 1;
  kind_names[n_kinds] = name;
  return n_kinds++;
}

static int
context_index(const char *name)
{
  for (int c = 0; c < n_contexts; ++c)
    if (strcmp(context_names[c], name) == 0)
      return c;
  if (n_contexts == MAX_CONTEXTS)
    return MAX_CONTEXTS - 1;
  context_names[n_contexts] = strdup(name);
  return n_contexts++;
}

static void
read_prefixes(void)
{
  n_prefixes        = 0;
  const char *value = getenv("MPI_COUNTER_FRAME_PREFIXES");
  if (value == NULL || *value == '\0')
    return;
  char *copy = strdup(value), *save = NULL;
  for (char *p = strtok_r(copy, ",", &save); p != NULL && n_prefixes < 16;
       p       = strtok_r(NULL, ",", &save))
    prefixes[n_prefixes++] = p;
}

// The symbol index (>= 0) of the function holding @p address if its name
// matches a prefix, else -1. Cached per address.
static int
frame_symbol(void *address)
{
  size_t slot = ((uintptr_t)address >> 2) * 2654435761u % ADDRESS_CACHE;
  for (size_t probe = 0; probe < ADDRESS_CACHE; ++probe)
    {
      const size_t s = (slot + probe) % ADDRESS_CACHE;
      if (address_cache[s].address == address)
        return address_cache[s].symbol;
      if (address_cache[s].address == NULL)
        {
          int       symbol = -1;
          Dl_info   info;
          ElfW(Sym) *entry = NULL;
          // A return address may be one past the call's function (noreturn
          // calls); look up the byte before it.
          void *const inside = (char *)address - 1;
          if (dladdr1(inside, &info, (void **)&entry, RTLD_DL_SYMENT) != 0 &&
              info.dli_sname != NULL && entry != NULL &&
              (char *)inside >= (char *)info.dli_saddr &&
              (char *)inside < (char *)info.dli_saddr + entry->st_size)
            for (int p = 0; p < n_prefixes; ++p)
              if (strncmp(info.dli_sname, prefixes[p], strlen(prefixes[p])) ==
                  0)
                {
                  for (symbol = 0; symbol < n_symbols; ++symbol)
                    if (strcmp(symbol_names[symbol], info.dli_sname) == 0)
                      break;
                  if (symbol == n_symbols)
                    {
                      if (n_symbols == MAX_CONTEXTS)
                        symbol = -1;
                      else
                        symbol_names[n_symbols++] = strdup(info.dli_sname);
                    }
                  break;
                }
          address_cache[s].address = address;
          address_cache[s].symbol  = symbol;
          return symbol;
        }
    }
  return -1; // cache full
}

// The context of the current call: "inner<-outer" of the matching frames.
static int
current_context(void)
{
  if (n_prefixes < 0)
    read_prefixes();
  if (n_prefixes == 0)
    return context_index("-");
  void     *frames[MAX_FRAMES];
  const int n_frames = backtrace(frames, MAX_FRAMES);
  int       found[2] = {-1, -1}, n_found = 0;
  for (int f = 1; f < n_frames && n_found < 2; ++f)
    {
      const int symbol = frame_symbol(frames[f]);
      if (symbol >= 0 && (n_found == 0 || found[0] != symbol))
        found[n_found++] = symbol;
    }
  if (n_found == 0)
    return context_index("-");
  char name[8192];
  if (n_found == 1)
    snprintf(name, sizeof(name), "%s", symbol_names[found[0]]);
  else
    snprintf(name,
             sizeof(name),
             "%s<-%s",
             symbol_names[found[0]],
             symbol_names[found[1]]);
  return context_index(name);
}

static void
add(const int context, const int kind, const uint64_t bytes)
{
  Counter *c = &counters[context * MAX_KINDS + kind];
  c->messages += 1;
  c->bytes += bytes;
}

static uint64_t
type_bytes(const int count, MPI_Datatype type)
{
  if (type == MPI_DATATYPE_NULL || count <= 0)
    return 0;
  int size = 0;
  PMPI_Type_size(type, &size);
  return (uint64_t)count * (uint64_t)size;
}

static const char *
tag_kind(const int tag)
{
  if (tag >= 329 && tag <= 331)
    return "p2p:particles";
  if (tag == 300 || tag == 301)
    return "p2p:some-to-some";
  if (tag >= 336 && tag <= 748)
    return "p2p:ghost";
  if (tag >= 300 && tag <= 760)
    return "p2p:dealii-other";
  if (tag == 1100)
    return "p2p:fmpm-points";
  if (tag == 1101)
    return "p2p:fmpm-contact";
  if (tag >= 24050 && tag <= 24099)
    return "p2p:epetra";
  return "p2p:other";
}

static void
count_send(const int tag, const int dest, const uint64_t bytes)
{
  pthread_mutex_lock(&lock);
  const int kind = kind_index(tag_kind(tag));
  add(current_context(), kind, bytes);
  if (dest >= 0 && dest < MAX_PEERS)
    peers[kind][dest / 64] |= (uint64_t)1 << (dest % 64);
  Counter *t = &tags[tag >= 0 && tag < MAX_TAGS ? tag : MAX_TAGS];
  t->messages += 1;
  t->bytes += bytes;
  pthread_mutex_unlock(&lock);
}

static void
count_collective(MPI_Comm comm, const char *self_name, const char *name,
                 const uint64_t bytes)
{
  int size = 2;
  if (comm != MPI_COMM_NULL)
    PMPI_Comm_size(comm, &size);
  pthread_mutex_lock(&lock);
  add(current_context(), kind_index(size == 1 ? self_name : name), bytes);
  pthread_mutex_unlock(&lock);
}

#define COLLECTIVE(comm, call, bytes) \
  count_collective(comm, "self:" call, "coll:" call, bytes)

static int
comm_size(MPI_Comm comm)
{
  int size = 1;
  PMPI_Comm_size(comm, &size);
  return size;
}

static int
comm_rank(MPI_Comm comm)
{
  int rank = 0;
  PMPI_Comm_rank(comm, &rank);
  return rank;
}

static uint64_t
sum_bytes(const int counts[], MPI_Datatype type, const int n)
{
  uint64_t sum = 0;
  for (int i = 0; i < n; ++i)
    sum += type_bytes(counts[i], type);
  return sum;
}

// The counter table, allocated when the library is loaded.
__attribute__((constructor)) static void
initialize(void)
{
  counters = calloc((size_t)MAX_CONTEXTS * MAX_KINDS, sizeof(Counter));
}

// ---------------------------------------------------------------- p2p

// The blocking and nonblocking sends: count, then call PMPI_<name>.
#define COUNTED_SEND(name)                                                     \
  int MPI_##name(const void *buf, int count, MPI_Datatype type, int dest,     \
                 int tag, MPI_Comm comm)                                       \
  {                                                                            \
    count_send(tag, dest, type_bytes(count, type));                            \
    return PMPI_##name(buf, count, type, dest, tag, comm);                     \
  }
#define COUNTED_NONBLOCKING_SEND(name)                                         \
  int MPI_##name(const void *buf, int count, MPI_Datatype type, int dest,     \
                 int tag, MPI_Comm comm, MPI_Request *request)                 \
  {                                                                            \
    count_send(tag, dest, type_bytes(count, type));                            \
    return PMPI_##name(buf, count, type, dest, tag, comm, request);            \
  }

COUNTED_SEND(Send)
COUNTED_SEND(Ssend)
COUNTED_SEND(Rsend)
COUNTED_SEND(Bsend)
COUNTED_NONBLOCKING_SEND(Isend)
COUNTED_NONBLOCKING_SEND(Issend)
COUNTED_NONBLOCKING_SEND(Irsend)
COUNTED_NONBLOCKING_SEND(Ibsend)

int
MPI_Sendrecv(const void *sendbuf, int sendcount, MPI_Datatype sendtype,
             int dest, int sendtag, void *recvbuf, int recvcount,
             MPI_Datatype recvtype, int source, int recvtag, MPI_Comm comm,
             MPI_Status *status)
{
  if (dest != MPI_PROC_NULL)
    count_send(sendtag, dest, type_bytes(sendcount, sendtype));
  return PMPI_Sendrecv(sendbuf, sendcount, sendtype, dest, sendtag, recvbuf,
                       recvcount, recvtype, source, recvtag, comm, status);
}

int
MPI_Sendrecv_replace(void *buf, int count, MPI_Datatype type, int dest,
                     int sendtag, int source, int recvtag, MPI_Comm comm,
                     MPI_Status *status)
{
  if (dest != MPI_PROC_NULL)
    count_send(sendtag, dest, type_bytes(count, type));
  return PMPI_Sendrecv_replace(buf, count, type, dest, sendtag, source,
                               recvtag, comm, status);
}

// Persistent sends: remember the request, count at MPI_Start.
static void
remember_persistent(MPI_Request request, const int tag, const uint64_t bytes)
{
  pthread_mutex_lock(&lock);
  const int context = current_context();
  const int kind    = kind_index(tag_kind(tag));
  for (int i = 0; i < MAX_PERSISTENT; ++i)
    if (persistent[i].request == request ||
        persistent[i].request == MPI_REQUEST_NULL ||
        persistent[i].request == 0)
      {
        persistent[i].request = request;
        persistent[i].context = context;
        persistent[i].kind    = kind;
        persistent[i].bytes   = bytes;
        break;
      }
  pthread_mutex_unlock(&lock);
}

static void
start_persistent(MPI_Request request)
{
  pthread_mutex_lock(&lock);
  for (int i = 0; i < MAX_PERSISTENT; ++i)
    if (persistent[i].request == request && request != MPI_REQUEST_NULL)
      {
        add(persistent[i].context, persistent[i].kind, persistent[i].bytes);
        break;
      }
  pthread_mutex_unlock(&lock);
}

#define SEND_INIT(NAME)                                                    \
  int MPI_##NAME(const void *buf, int count, MPI_Datatype type, int dest,  \
                 int tag, MPI_Comm comm, MPI_Request *request)             \
  {                                                                        \
    const int ierr =                                                       \
      PMPI_##NAME(buf, count, type, dest, tag, comm, request);             \
    if (ierr == MPI_SUCCESS)                                               \
      remember_persistent(*request, tag, type_bytes(count, type));         \
    return ierr;                                                           \
  }
SEND_INIT(Send_init)
SEND_INIT(Ssend_init)
SEND_INIT(Rsend_init)
SEND_INIT(Bsend_init)

int
MPI_Start(MPI_Request *request)
{
  start_persistent(*request);
  return PMPI_Start(request);
}

int
MPI_Startall(int n, MPI_Request requests[])
{
  for (int i = 0; i < n; ++i)
    start_persistent(requests[i]);
  return PMPI_Startall(n, requests);
}

int
MPI_Request_free(MPI_Request *request)
{
  pthread_mutex_lock(&lock);
  for (int i = 0; i < MAX_PERSISTENT; ++i)
    if (persistent[i].request == *request && *request != MPI_REQUEST_NULL)
      {
        persistent[i].request = MPI_REQUEST_NULL;
        break;
      }
  pthread_mutex_unlock(&lock);
  return PMPI_Request_free(request);
}

// ---------------------------------------------------------- collectives

int
MPI_Barrier(MPI_Comm comm)
{
  COLLECTIVE(comm, "MPI_Barrier", 0);
  return PMPI_Barrier(comm);
}

int
MPI_Ibarrier(MPI_Comm comm, MPI_Request *request)
{
  COLLECTIVE(comm, "MPI_Ibarrier", 0);
  return PMPI_Ibarrier(comm, request);
}

int
MPI_Bcast(void *buf, int count, MPI_Datatype type, int root, MPI_Comm comm)
{
  COLLECTIVE(comm, "MPI_Bcast", type_bytes(count, type));
  return PMPI_Bcast(buf, count, type, root, comm);
}

int
MPI_Ibcast(void *buf, int count, MPI_Datatype type, int root, MPI_Comm comm,
           MPI_Request *request)
{
  COLLECTIVE(comm, "MPI_Ibcast", type_bytes(count, type));
  return PMPI_Ibcast(buf, count, type, root, comm, request);
}

int
MPI_Allreduce(const void *sendbuf, void *recvbuf, int count, MPI_Datatype type,
              MPI_Op op, MPI_Comm comm)
{
  COLLECTIVE(comm, "MPI_Allreduce", type_bytes(count, type));
  return PMPI_Allreduce(sendbuf, recvbuf, count, type, op, comm);
}

int
MPI_Iallreduce(const void *sendbuf, void *recvbuf, int count,
               MPI_Datatype type, MPI_Op op, MPI_Comm comm,
               MPI_Request *request)
{
  COLLECTIVE(comm, "MPI_Iallreduce", type_bytes(count, type));
  return PMPI_Iallreduce(sendbuf, recvbuf, count, type, op, comm, request);
}

int
MPI_Reduce(const void *sendbuf, void *recvbuf, int count, MPI_Datatype type,
           MPI_Op op, int root, MPI_Comm comm)
{
  COLLECTIVE(comm, "MPI_Reduce", type_bytes(count, type));
  return PMPI_Reduce(sendbuf, recvbuf, count, type, op, root, comm);
}

int
MPI_Ireduce(const void *sendbuf, void *recvbuf, int count, MPI_Datatype type,
            MPI_Op op, int root, MPI_Comm comm, MPI_Request *request)
{
  COLLECTIVE(comm, "MPI_Ireduce", type_bytes(count, type));
  return PMPI_Ireduce(sendbuf, recvbuf, count, type, op, root, comm, request);
}

int
MPI_Reduce_scatter(const void *sendbuf, void *recvbuf, const int recvcounts[],
                   MPI_Datatype type, MPI_Op op, MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Reduce_scatter",
             sum_bytes(recvcounts, type, comm_size(comm)));
  return PMPI_Reduce_scatter(sendbuf, recvbuf, recvcounts, type, op, comm);
}

int
MPI_Reduce_scatter_block(const void *sendbuf, void *recvbuf, int recvcount,
                         MPI_Datatype type, MPI_Op op, MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Reduce_scatter_block",
             type_bytes(recvcount, type) * (uint64_t)comm_size(comm));
  return PMPI_Reduce_scatter_block(sendbuf, recvbuf, recvcount, type, op,
                                   comm);
}

int
MPI_Scan(const void *sendbuf, void *recvbuf, int count, MPI_Datatype type,
         MPI_Op op, MPI_Comm comm)
{
  COLLECTIVE(comm, "MPI_Scan", type_bytes(count, type));
  return PMPI_Scan(sendbuf, recvbuf, count, type, op, comm);
}

int
MPI_Exscan(const void *sendbuf, void *recvbuf, int count, MPI_Datatype type,
           MPI_Op op, MPI_Comm comm)
{
  COLLECTIVE(comm, "MPI_Exscan", type_bytes(count, type));
  return PMPI_Exscan(sendbuf, recvbuf, count, type, op, comm);
}

int
MPI_Allgather(const void *sendbuf, int sendcount, MPI_Datatype sendtype,
              void *recvbuf, int recvcount, MPI_Datatype recvtype,
              MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Allgather",
             sendbuf == MPI_IN_PLACE ? type_bytes(recvcount, recvtype) :
                                       type_bytes(sendcount, sendtype));
  return PMPI_Allgather(sendbuf, sendcount, sendtype, recvbuf, recvcount,
                        recvtype, comm);
}

int
MPI_Iallgather(const void *sendbuf, int sendcount, MPI_Datatype sendtype,
               void *recvbuf, int recvcount, MPI_Datatype recvtype,
               MPI_Comm comm, MPI_Request *request)
{
  COLLECTIVE(comm,
             "MPI_Iallgather",
             sendbuf == MPI_IN_PLACE ? type_bytes(recvcount, recvtype) :
                                       type_bytes(sendcount, sendtype));
  return PMPI_Iallgather(sendbuf, sendcount, sendtype, recvbuf, recvcount,
                         recvtype, comm, request);
}

int
MPI_Allgatherv(const void *sendbuf, int sendcount, MPI_Datatype sendtype,
               void *recvbuf, const int recvcounts[], const int displs[],
               MPI_Datatype recvtype, MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Allgatherv",
             sendbuf == MPI_IN_PLACE ?
               type_bytes(recvcounts[comm_rank(comm)], recvtype) :
               type_bytes(sendcount, sendtype));
  return PMPI_Allgatherv(sendbuf, sendcount, sendtype, recvbuf, recvcounts,
                         displs, recvtype, comm);
}

int
MPI_Gather(const void *sendbuf, int sendcount, MPI_Datatype sendtype,
           void *recvbuf, int recvcount, MPI_Datatype recvtype, int root,
           MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Gather",
             sendbuf == MPI_IN_PLACE ? type_bytes(recvcount, recvtype) :
                                       type_bytes(sendcount, sendtype));
  return PMPI_Gather(sendbuf, sendcount, sendtype, recvbuf, recvcount,
                     recvtype, root, comm);
}

int
MPI_Gatherv(const void *sendbuf, int sendcount, MPI_Datatype sendtype,
            void *recvbuf, const int recvcounts[], const int displs[],
            MPI_Datatype recvtype, int root, MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Gatherv",
             sendbuf == MPI_IN_PLACE ?
               type_bytes(recvcounts[comm_rank(comm)], recvtype) :
               type_bytes(sendcount, sendtype));
  return PMPI_Gatherv(sendbuf, sendcount, sendtype, recvbuf, recvcounts,
                      displs, recvtype, root, comm);
}

int
MPI_Scatter(const void *sendbuf, int sendcount, MPI_Datatype sendtype,
            void *recvbuf, int recvcount, MPI_Datatype recvtype, int root,
            MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Scatter",
             comm_rank(comm) == root ?
               type_bytes(sendcount, sendtype) * (uint64_t)comm_size(comm) :
               0);
  return PMPI_Scatter(sendbuf, sendcount, sendtype, recvbuf, recvcount,
                      recvtype, root, comm);
}

int
MPI_Scatterv(const void *sendbuf, const int sendcounts[], const int displs[],
             MPI_Datatype sendtype, void *recvbuf, int recvcount,
             MPI_Datatype recvtype, int root, MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Scatterv",
             comm_rank(comm) == root ?
               sum_bytes(sendcounts, sendtype, comm_size(comm)) :
               0);
  return PMPI_Scatterv(sendbuf, sendcounts, displs, sendtype, recvbuf,
                       recvcount, recvtype, root, comm);
}

int
MPI_Alltoall(const void *sendbuf, int sendcount, MPI_Datatype sendtype,
             void *recvbuf, int recvcount, MPI_Datatype recvtype,
             MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Alltoall",
             (sendbuf == MPI_IN_PLACE ? type_bytes(recvcount, recvtype) :
                                        type_bytes(sendcount, sendtype)) *
               (uint64_t)comm_size(comm));
  return PMPI_Alltoall(sendbuf, sendcount, sendtype, recvbuf, recvcount,
                       recvtype, comm);
}

int
MPI_Alltoallv(const void *sendbuf, const int sendcounts[],
              const int sdispls[], MPI_Datatype sendtype, void *recvbuf,
              const int recvcounts[], const int rdispls[],
              MPI_Datatype recvtype, MPI_Comm comm)
{
  COLLECTIVE(comm,
             "MPI_Alltoallv",
             sendbuf == MPI_IN_PLACE ?
               sum_bytes(recvcounts, recvtype, comm_size(comm)) :
               sum_bytes(sendcounts, sendtype, comm_size(comm)));
  return PMPI_Alltoallv(sendbuf, sendcounts, sdispls, sendtype, recvbuf,
                        recvcounts, rdispls, recvtype, comm);
}

int
MPI_Alltoallw(const void *sendbuf, const int sendcounts[],
              const int sdispls[], const MPI_Datatype sendtypes[],
              void *recvbuf, const int recvcounts[], const int rdispls[],
              const MPI_Datatype recvtypes[], MPI_Comm comm)
{
  uint64_t  bytes = 0;
  const int n     = comm_size(comm);
  for (int i = 0; i < n; ++i)
    bytes += sendbuf == MPI_IN_PLACE ? type_bytes(recvcounts[i], recvtypes[i]) :
                                       type_bytes(sendcounts[i], sendtypes[i]);
  COLLECTIVE(comm, "MPI_Alltoallw", bytes);
  return PMPI_Alltoallw(sendbuf, sendcounts, sdispls, sendtypes, recvbuf,
                        recvcounts, rdispls, recvtypes, comm);
}

// ------------------------------------------------------------ one-sided

static void
count_rma(const char *name, const uint64_t bytes)
{
  pthread_mutex_lock(&lock);
  add(current_context(), kind_index(name), bytes);
  pthread_mutex_unlock(&lock);
}

int
MPI_Put(const void *origin, int origin_count, MPI_Datatype origin_type,
        int target, MPI_Aint target_disp, int target_count,
        MPI_Datatype target_type, MPI_Win win)
{
  count_rma("rma:MPI_Put", type_bytes(origin_count, origin_type));
  return PMPI_Put(origin, origin_count, origin_type, target, target_disp,
                  target_count, target_type, win);
}

int
MPI_Get(void *origin, int origin_count, MPI_Datatype origin_type, int target,
        MPI_Aint target_disp, int target_count, MPI_Datatype target_type,
        MPI_Win win)
{
  count_rma("rma:MPI_Get", type_bytes(origin_count, origin_type));
  return PMPI_Get(origin, origin_count, origin_type, target, target_disp,
                  target_count, target_type, win);
}

int
MPI_Accumulate(const void *origin, int origin_count, MPI_Datatype origin_type,
               int target, MPI_Aint target_disp, int target_count,
               MPI_Datatype target_type, MPI_Op op, MPI_Win win)
{
  count_rma("rma:MPI_Accumulate", type_bytes(origin_count, origin_type));
  return PMPI_Accumulate(origin, origin_count, origin_type, target,
                         target_disp, target_count, target_type, op, win);
}

// --------------------------------------------------------------- output

static void
write_json_string(FILE *out, const char *s)
{
  fputc('"', out);
  for (; *s; ++s)
    if (*s == '"' || *s == '\\')
      fprintf(out, "\\%c", *s);
    else if ((unsigned char)*s < 0x20)
      fprintf(out, "\\u%04x", *s);
    else
      fputc(*s, out);
  fputc('"', out);
}

int
MPI_Finalize(void)
{
  const char *directory = getenv("MPI_COUNTER_DIR");
  if (directory != NULL && *directory != '\0' && counters != NULL)
    {
      const int rank = comm_rank(MPI_COMM_WORLD);
      const int size = comm_size(MPI_COMM_WORLD);
      char      path[4096];
      snprintf(path, sizeof(path), "%s/rank-%d.json", directory, rank);
      FILE *out = fopen(path, "w");
      if (out != NULL)
        {
          pthread_mutex_lock(&lock);
          fprintf(out, "{\"rank\": %d, \"size\": %d, \"counts\": [", rank, size);
          int first = 1;
          for (int c = 0; c < n_contexts; ++c)
            for (int k = 0; k < n_kinds; ++k)
              {
                const Counter *counter = &counters[c * MAX_KINDS + k];
                if (counter->messages == 0)
                  continue;
                fputs(first ? "[" : ", [", out);
                first = 0;
                write_json_string(out, context_names[c]);
                fputs(", ", out);
                write_json_string(out, kind_names[k]);
                fprintf(out,
                        ", %llu, %llu]",
                        (unsigned long long)counter->messages,
                        (unsigned long long)counter->bytes);
              }
          fputs("], \"tags\": [", out);
          first = 1;
          for (int t = 0; t <= MAX_TAGS; ++t)
            if (tags[t].messages > 0)
              {
                fprintf(out,
                        "%s[%d, %llu, %llu]",
                        first ? "" : ", ",
                        t == MAX_TAGS ? -1 : t,
                        (unsigned long long)tags[t].messages,
                        (unsigned long long)tags[t].bytes);
                first = 0;
              }
          fputs("], \"peers\": {", out);
          first = 1;
          for (int k = 0; k < n_kinds; ++k)
            {
              int n = 0;
              for (int w = 0; w < MAX_PEERS / 64; ++w)
                n += __builtin_popcountll(peers[k][w]);
              if (n == 0)
                continue;
              fputs(first ? "" : ", ", out);
              first = 0;
              write_json_string(out, kind_names[k]);
              fprintf(out, ": %d", n);
            }
          fputs("}}\n", out);
          pthread_mutex_unlock(&lock);
          fclose(out);
        }
      else
        fprintf(stderr, "mpi_counter: cannot write %s\n", path);
    }
  return PMPI_Finalize();
}
