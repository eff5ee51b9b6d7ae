// File access and format dispatch. The parsers are in io_text.cpp (OBJ, OFF) and io_ply.cpp (PLY),
// the writers in io_write.cpp.
#include "qsp/io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <memory>
#include <string>
#include <string_view>

#include "io_numbers.h"
#include "plural.h"
#include "qsp/error.h"
#include "qsp/mesh.h"

namespace qsp {
namespace {

[[noreturn]] void fail_io(const std::string& path, const std::string& what) {
  throw Error(ErrorCode::kIo, path + ": " + what);
}
[[noreturn]] void fail_errno(const std::string& path, const std::string& what, int err) {
  if (err == 0) fail_io(path, what);
  fail_io(path, what.empty() ? std::strerror(err) : what + ": " + std::strerror(err));
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

// Checks what every writer relies on, so a written file always reads back.
void check_writable(const QuadMesh& mesh, const char* what) {
  if (mesh.positions.size() % 3 != 0 || mesh.quads.size() % 4 != 0) {
    throw Error(ErrorCode::kUsage, std::string(what) + ": positions or quads have a partial entry");
  }
  if (mesh.vertex_count() > kMaxVertices || mesh.face_count() > kMaxFaces) {
    throw Error(ErrorCode::kLimit, std::string(what) + ": mesh exceeds qsp's vertex or face limit");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!std::isfinite(mesh.positions[i])) {
      throw Error(ErrorCode::kBadNumber,
                  std::string(what) + ": vertex " + std::to_string(i / 3) + " has a non-finite coordinate");
    }
  }
  const std::size_t v = mesh.vertex_count();
  for (std::size_t i = 0; i < mesh.quads.size(); ++i) {
    if (mesh.quads[i] >= v) {
      throw Error(ErrorCode::kBadIndex, std::string(what) + ": face " + std::to_string(i / 4) +
                                            " refers to vertex " + std::to_string(mesh.quads[i]) + " of " +
                                            std::to_string(v));
    }
  }
}

bool write_all(int fd, std::string_view bytes, int* err) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      *err = errno;
      return false;
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

// Makes the names just created in `dir` durable.
void sync_dir(const std::string& dir) {
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

// Renames `from` over `to`, 0 or the errno of the failure. ext4 writes out a file renamed over another
// at once (its auto_da_alloc), which only --sync asks for: 0.5 ms of a 17 ms compress wherever the
// output is replaced. So the two names are exchanged (`to` is never missing: it is the old file or the
// new one) and the old file, now under `from`, removed; a plain rename where exchanging is not
// supported or `to` does not exist.
int replace_name(const std::string& from, const std::string& to) {
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE) == 0) {
    if (::unlink(from.c_str()) == 0) return 0;
    const int err = errno;  // `to` was a directory: it goes back
    ::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE);
    return err;
  }
  return ::rename(from.c_str(), to.c_str()) == 0 ? 0 : errno;
}

void (*before_rename_hook)() = nullptr;  // set_before_rename_hook

void before_rename() {
  if (before_rename_hook) before_rename_hook();
}

// Linux: writes `bytes` to an unnamed file in `dir` (O_TMPFILE), then gives it its name. A process
// killed at any point before that leaves nothing behind, not even a temporary file. Without -f the
// name is created by linkat, which fails if it exists (atomic no-replace); with -f the file is
// linked under a hidden temporary name and put in the target's place (replace_name; named only
// between those two calls). Returns false, having left nothing, where O_TMPFILE or /proc is unavailable.
bool write_anonymous_then_link(const std::string& path, const std::string& dir, const std::string& name,
                               std::string_view bytes, bool overwrite, bool sync) {
#ifdef O_TMPFILE
  const int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int e = errno;
    if (e == EOPNOTSUPP || e == EISDIR || e == EINVAL)
      return false;  // filesystem or kernel without O_TMPFILE
    fail_errno(path, "cannot create a temporary file in " + dir, e);
  }
  int err = 0;
  const auto fail_closed = [&](const std::string& what, int e) {
    ::close(fd);
    fail_errno(path, what, e);
  };
  if (!write_all(fd, bytes, &err)) fail_closed("cannot write", err);
  if (sync && ::fsync(fd) != 0) fail_closed("cannot flush to disk", errno);
  before_rename();
  const std::string self = "/proc/self/fd/" + std::to_string(fd);
  std::string target = path;
  if (overwrite) {
    // Hidden, and short enough for NAME_MAX whatever the target's name length.
    const std::string base = (dir == "/" ? "" : dir) + "/." + name.substr(0, 200) + ".tmp.";
    for (unsigned attempt = 0;; ++attempt) {
      target = base + std::to_string(::getpid()) + "." + std::to_string(attempt);
      if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, target.c_str(), AT_SYMLINK_FOLLOW) == 0) break;
      err = errno;
      if (err == EEXIST && attempt < 100) continue;
      if (err == ENOENT && ::access("/proc/self/fd", X_OK) != 0) {
        ::close(fd);
        return false;  // no /proc
      }
      fail_closed("cannot create a temporary file in " + dir, err);
    }
    ::close(fd);
    if ((err = replace_name(target, path)) != 0) {
      ::unlink(target.c_str());
      fail_errno(path, "cannot rename into place", err);
    }
  } else {
    if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, path.c_str(), AT_SYMLINK_FOLLOW) != 0) {
      err = errno;
      if (err == EEXIST) fail_closed("already exists (refusing to overwrite it)", 0);
      if (err == ENOENT && ::access("/proc/self/fd", X_OK) != 0) {
        ::close(fd);
        return false;  // no /proc
      }
      fail_closed("cannot create", err);
    }
    ::close(fd);
  }
  if (sync) sync_dir(dir);  // the new name itself durable
  return true;
#else
  (void)path, (void)dir, (void)name, (void)bytes, (void)overwrite, (void)sync;
  return false;
#endif
}

}  // namespace

MeshFormat format_from_path(std::string_view path) {
  const std::size_t slash = path.find_last_of('/');
  const std::string_view name = slash == std::string_view::npos ? path : path.substr(slash + 1);
  const std::size_t dot = name.find_last_of('.');
  if (dot == std::string_view::npos || dot == 0) return MeshFormat::kUnknown;
  const std::string ext = lower(name.substr(dot + 1));
  if (ext == "obj") return MeshFormat::kObj;
  if (ext == "off") return MeshFormat::kOff;
  if (ext == "ply") return MeshFormat::kPly;
  if (ext == "qsp") return MeshFormat::kQsp;
  return MeshFormat::kUnknown;
}

namespace {

// One count of a ReadReport: its category and its words.
struct ReportItem {
  std::uint64_t ReadReport::*count;
  Category category;
  const char* one;
  const char* many;
};

// In kCategoryNames order, so a description lists the categories as --drop does.
constexpr ReportItem kReportItems[] = {
    {&ReadReport::texcoords, kCategoryUv, "texture coordinate", "texture coordinates"},
    {&ReadReport::faces_with_texcoords, kCategoryUv, "face with texture coordinate indices",
     "faces with texture coordinate indices"},
    {&ReadReport::normals, kCategoryNormal, "normal", "normals"},
    {&ReadReport::faces_with_normals, kCategoryNormal, "face with normal indices",
     "faces with normal indices"},
    {&ReadReport::vertex_colors, kCategoryColor, "vertex colour", "vertex colours"},
    {&ReadReport::face_colors, kCategoryColor, "face colour", "face colours"},
    {&ReadReport::groups, kCategoryGroup, "group/object statement", "group/object statements"},
    {&ReadReport::materials, kCategoryMaterial, "material statement", "material statements"},
    {&ReadReport::smoothing, kCategorySmoothing, "smoothing group statement", "smoothing group statements"},
    {&ReadReport::tags, kCategoryTag, "subdivision tag", "subdivision tags"},
    {&ReadReport::comments, kCategoryComment, "leading comment line", "leading comment lines"},
    {&ReadReport::vertex_weights, kCategoryExtra, "vertex weight (v x y z w)", "vertex weights (v x y z w)"},
    {&ReadReport::kept_lines, kCategoryExtra, "line qsp keeps only as text", "lines qsp keeps only as text"},
    {&ReadReport::other_properties, kCategoryExtra, "other PLY property value", "other PLY property values"},
    {&ReadReport::obj_info, kCategoryExtra, "PLY obj_info line", "PLY obj_info lines"},
};

}  // namespace

unsigned ReadReport::categories() const {
  unsigned out = 0;
  for (const ReportItem& item : kReportItems) {
    if (this->*item.count) out |= item.category;
  }
  return out;
}

std::string ReadReport::describe_extra_data(std::string_view source, unsigned categories) const {
  std::string out, group;  // group: the current category's items
  const auto close = [&](Category c) {
    if (group.empty()) return;
    if (!out.empty()) out += ", ";
    out.append(group).append(" (").append(category_name(c)).append(")");
    group.clear();
  };
  for (std::size_t i = 0; i < std::size(kReportItems); ++i) {
    const ReportItem& item = kReportItems[i];
    const std::uint64_t n = this->*item.count;
    if (n && (categories & item.category)) {
      detail::append_count(group, n, item.one, item.many);
      if (item.count == &ReadReport::kept_lines) {
        group.append(", the first at ").append(source);
        if (first_kept.line) group.append(":").append(std::to_string(first_kept.line));
        group.append(": ").append(first_kept.message);
      }
    }
    if (i + 1 == std::size(kReportItems) || kReportItems[i + 1].category != item.category)
      close(item.category);
  }
  return out;
}

void ReadReport::note_kept(std::uint64_t line, std::string_view what) {
  if (kept_lines++ == 0) first_kept = {line, std::string(what)};
}

std::string ReadReport::describe_rounding(std::string_view source) const {
  if (rounded_coordinates == 0) return {};
  std::string out(source);
  if (first_rounded.line) out.append(":").append(std::to_string(first_rounded.line));
  out.append(": vertex ").append(std::to_string(first_rounded.vertex)).append(" has ");
  out.append(first_rounded.value).append(", which float32 holds only as ");
  detail::append_float(out, first_rounded.nearest);
  if (rounded_coordinates > 1) {
    out.append(" (and ").append(std::to_string(rounded_coordinates - 1));
    out.append(rounded_coordinates == 2 ? " more coordinate like it)" : " more coordinates like it)");
  }
  return out;
}

void ReadReport::note_rounded(std::uint64_t line, std::uint64_t vertex, std::string_view value,
                              float nearest) {
  // At most 40 characters of the text, as every reader message quotes a token.
  constexpr std::size_t kShown = 40;
  if (rounded_coordinates++ == 0)
    first_rounded = {
        line, vertex,
        value.size() <= kShown ? std::string(value) : std::string(value.substr(0, kShown)) + "...", nearest};
}

// The QuadMesh writers are the Mesh writers (io_write.cpp) on the same positions and quads; a
// QuadMesh may hold a face that repeats a vertex, which they write as it is.
std::string write_obj(const QuadMesh& mesh, const std::vector<std::string>& comments) {
  check_writable(mesh, "write_obj");
  Mesh m = from_quad_mesh(mesh);
  m.comments = comments;
  return write_obj_mesh(m);
}

std::string write_off(const QuadMesh& mesh, const std::vector<std::string>& comments) {
  check_writable(mesh, "write_off");
  Mesh m = from_quad_mesh(mesh);
  m.comments = comments;
  return write_off_mesh(m);
}

namespace {

// The whole file in an uninitialised buffer: for a 12 MB mesh, zero-filling a std::string first
// costs about as much as the read itself. `size` is what was read.
struct FileBuffer {
  std::unique_ptr<char[]> data;
  std::size_t size = 0;
  std::string_view view() const { return {data.get(), size}; }
};

FileBuffer read_file_raw(const std::string& path) {
  const bool is_stdin = path == "-";
  const int fd = is_stdin ? STDIN_FILENO : ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail_errno(path, "", errno);
  // Size the buffer from fstat (+1 so the read that sees EOF needs no regrowth), but read until
  // EOF rather than trusting it: pipes have no size and files can grow.
  struct stat st {};
  constexpr std::size_t kChunk = 1 << 20;
  const bool sized = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0;
  std::size_t capacity = sized ? static_cast<std::size_t>(st.st_size) + 1 : kChunk;
  FileBuffer buf;
  buf.data.reset(new char[capacity]);
  for (;;) {
    if (buf.size == capacity) {
      std::unique_ptr<char[]> bigger(new char[2 * capacity]);
      std::memcpy(bigger.get(), buf.data.get(), buf.size);
      buf.data = std::move(bigger);
      capacity *= 2;
    }
    const ssize_t n = ::read(fd, buf.data.get() + buf.size, capacity - buf.size);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      if (!is_stdin) ::close(fd);
      fail_errno(path, "", err);
    }
    if (n == 0) break;
    buf.size += static_cast<std::size_t>(n);
  }
  if (!is_stdin) ::close(fd);
  return buf;
}

}  // namespace

namespace {

// An OFF keyword line ("OFF", "COFF", "STCNOFF", ... with nothing but blanks after it).
bool off_header(std::string_view line) {
  const std::size_t end = line.find_first_of(" \t");
  const std::string_view word = line.substr(0, end);
  if (end != std::string_view::npos && line.find_first_not_of(" \t", end) != std::string_view::npos)
    return false;
  return word.size() >= 3 && word.size() <= 10 && word.ends_with("OFF") &&
         word.find_first_not_of("STCN4nOF") == std::string_view::npos;
}

}  // namespace

std::vector<std::string> leading_comments(std::string_view text) {
  std::vector<std::string> out;
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  std::size_t p = 0;
  bool header_seen = false;
  while (p < text.size()) {
    std::size_t e = p;  // the line's end: LF, or a CR not followed by LF (CRLF: at the CR)
    while (e < text.size() && text[e] != '\n' && text[e] != '\r') ++e;
    std::string_view line = text.substr(p, e - p);
    p = e + (e + 1 < text.size() && text[e] == '\r' && text[e + 1] == '\n' ? 2 : 1);
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string_view::npos) continue;  // blank
    if (out.empty() && !header_seen && off_header(line.substr(first))) {
      header_seen = true;  // OFF's keyword line: the block may follow it
      continue;
    }
    if (line[first] != '#') break;
    out.emplace_back(line.substr(first + 1));
  }
  return out;
}

std::string read_file_bytes(const std::string& path) {
  const FileBuffer buf = read_file_raw(path);
  return std::string(buf.view());
}

namespace {

// The format to read `path` as: kObj, kOff or kPly; throws for anything else.
MeshFormat readable_format(const std::string& path, MeshFormat format) {
  if (format == MeshFormat::kUnknown) format = format_from_path(path);
  if (format == MeshFormat::kObj || format == MeshFormat::kOff || format == MeshFormat::kPly) return format;
  if (format == MeshFormat::kQsp) {
    throw Error(ErrorCode::kUnsupported, path + ": a .qsp file is compressed data, not a mesh to read here");
  }
  throw Error(ErrorCode::kUnsupported,
              path + (path == "-" ? ": give the format of standard input (obj, off or ply)"
                                  : ": unknown mesh format (expected .obj, .off or .ply)"));
}

}  // namespace

QuadMesh read_mesh_file(const std::string& path, ReadReport* report, MeshFormat format) {
  format = readable_format(path, format);
  if (format == MeshFormat::kPly) return read_ply_file(path, report);
  const FileBuffer text = read_file_raw(path);
  return format == MeshFormat::kObj ? read_obj(text.view(), path, report)
                                    : read_off(text.view(), path, report);
}

Mesh read_mesh(const std::string& path, ReadNotes* notes, MeshFormat format) {
  format = readable_format(path, format);
  const FileBuffer bytes = read_file_raw(path);
  return format == MeshFormat::kObj   ? read_obj_mesh(bytes.view(), path, notes)
         : format == MeshFormat::kOff ? read_off_mesh(bytes.view(), path, notes)
                                      : read_ply_mesh(bytes.view(), path, notes);
}

void set_before_rename_hook(void (*hook)()) { before_rename_hook = hook; }

void write_file_atomic(const std::string& path, std::string_view bytes, bool overwrite, bool sync) {
  int err = 0;
  if (path == "-") {
    if (!write_all(STDOUT_FILENO, bytes, &err)) fail_errno("-", "cannot write standard output", err);
    return;
  }
  if (path.empty()) fail_io(path, "empty output path");
  struct stat st {};
  const bool exists = ::lstat(path.c_str(), &st) == 0;
  if (exists && !overwrite) fail_io(path, "already exists (refusing to overwrite it)");
  if (exists && S_ISDIR(st.st_mode)) fail_io(path, "is a directory");
  if (exists && !S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode)) {
    // A device or pipe (/dev/null, /dev/full, a FIFO) is written in place: renaming a file over it
    // would replace the device node.
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) fail_errno(path, "cannot open", errno);
    if (!write_all(fd, bytes, &err)) {
      ::close(fd);
      fail_errno(path, "cannot write", err);
    }
    if (::close(fd) != 0) fail_errno(path, "cannot close", errno);
    return;
  }
  const std::size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  if (write_anonymous_then_link(path, dir, name, bytes, overwrite, sync)) return;
  // Hidden, and short enough for NAME_MAX whatever the target's name length.
  std::string temp = (dir == "/" ? "" : dir) + "/." + name.substr(0, 200) + ".tmp.XXXXXX";
  const int fd = ::mkstemp(temp.data());
  if (fd < 0) fail_errno(path, "cannot create a temporary file in " + dir, errno);

  const auto fail_and_remove = [&](const std::string& what, int e) {
    ::unlink(temp.c_str());
    fail_errno(path, what, e);
  };
  // mkstemp makes the file 0600; give the result the permissions an ordinary create would.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  if (::fchmod(fd, 0666 & ~mask) != 0) {
    err = errno;
    ::close(fd);
    fail_and_remove("cannot set permissions", err);
  }
  if (!write_all(fd, bytes, &err)) {
    ::close(fd);
    fail_and_remove("cannot write", err);
  }
  if (sync && ::fsync(fd) != 0) {
    err = errno;
    ::close(fd);
    fail_and_remove("cannot flush to disk", err);
  }
  if (::close(fd) != 0) fail_and_remove("cannot close", errno);
  before_rename();

  if (overwrite) {
    if ((err = replace_name(temp, path)) != 0) fail_and_remove("cannot rename into place", err);
  } else {
    // Atomic no-replace; the lstat above is only the early, friendly check.
    if (::renameat2(AT_FDCWD, temp.c_str(), AT_FDCWD, path.c_str(), RENAME_NOREPLACE) != 0) {
      err = errno;
      if (err == EEXIST) fail_and_remove("already exists (refusing to overwrite it)", 0);
      if (err != EINVAL && err != ENOSYS) fail_and_remove("cannot rename into place", err);
      // Filesystem without RENAME_NOREPLACE: fall back to check-then-rename.
      if (::lstat(path.c_str(), &st) == 0) fail_and_remove("already exists (refusing to overwrite it)", 0);
      if (::rename(temp.c_str(), path.c_str()) != 0) fail_and_remove("cannot rename into place", errno);
    }
  }
  if (sync) sync_dir(dir);  // the rename itself durable
}

}  // namespace qsp
