#include "plugins/elf_check.hpp"

#include <elf.h>

#include <cstdint>
#include <cstring>

namespace salsa {

namespace {

static_assert(sizeof(void*) == 8, "plugin files are checked as 64-bit ELF");

// What this host loads, fixed at compile time.
#if defined(__x86_64__)
constexpr std::uint16_t host_machine = EM_X86_64;
#elif defined(__aarch64__)
constexpr std::uint16_t host_machine = EM_AARCH64;
#elif defined(__riscv)
constexpr std::uint16_t host_machine = EM_RISCV;
#elif defined(__powerpc64__)
constexpr std::uint16_t host_machine = EM_PPC64;
#elif defined(__s390x__)
constexpr std::uint16_t host_machine = EM_S390;
#elif defined(__loongarch64)
constexpr std::uint16_t host_machine = EM_LOONGARCH;
#else
#error "add this host's ELF machine number"
#endif
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
constexpr unsigned char host_data = ELFDATA2LSB;
#else
constexpr unsigned char host_data = ELFDATA2MSB;
#endif

std::string machine_name(std::uint16_t m) {
  switch (m) {
    case EM_386: return "32-bit x86";
    case EM_X86_64: return "x86-64";
    case EM_ARM: return "32-bit ARM";
    case EM_AARCH64: return "AArch64 (64-bit ARM)";
    case EM_RISCV: return "RISC-V";
    case EM_PPC64: return "PowerPC 64";
    case EM_S390: return "s390x";
    case EM_MIPS: return "MIPS";
    case EM_SPARCV9: return "SPARC v9";
    case EM_LOONGARCH: return "LoongArch";
  }
  return "ELF machine " + std::to_string(m);
}

std::string bytes(std::uint64_t n) { return std::to_string(n) + (n == 1 ? " byte" : " bytes"); }

std::string truncated(const std::string& what, std::uint64_t end, std::size_t size) {
  return "truncated: " + what + " ends at byte " + std::to_string(end) + ", the file has " + bytes(size) +
         " (a half-copied file?)";
}

/// Where [offset, offset + count × entry) ends, or 0 on overflow (no valid range ends at 0 here).
std::uint64_t end_of(std::uint64_t offset, std::uint64_t count, std::uint64_t entry) {
  std::uint64_t length = 0, end = 0;
  if (__builtin_mul_overflow(count, entry, &length) || __builtin_add_overflow(offset, length, &end)) return 0;
  return end;
}

/// A problem with a range of the file, or empty when it lies inside.
std::string outside(const std::string& what, std::uint64_t offset, std::uint64_t length, std::size_t size) {
  const std::uint64_t end = end_of(offset, 1, length);
  if (end == 0 && length != 0)
    return "damaged: " + what + " claims " + bytes(length) + " at byte " + std::to_string(offset) +
           ", past any file's end";
  return end > size ? truncated(what, end, size) : std::string();
}

template <class T>
T read(const unsigned char* at) {
  T out;
  std::memcpy(&out, at, sizeof out);  // no alignment assumed: the bytes may come from anywhere
  return out;
}

}  // namespace

std::string elf_problem(const unsigned char* data, std::size_t size) {
  // Identification: magic, class, byte order, version.
  if (size == 0) return "an empty file, not a shared library";
  const bool magic_so_far = std::memcmp(data, ELFMAG, size < SELFMAG ? size : SELFMAG) == 0;
  if (!magic_so_far) return "not a shared library (no ELF header)";
  if (size < sizeof(Elf64_Ehdr)) return truncated("the ELF header", sizeof(Elf64_Ehdr), size);
  const auto eh = read<Elf64_Ehdr>(data);
  if (eh.e_ident[EI_CLASS] == ELFCLASS32) return "a 32-bit library, this salsa is 64-bit";
  if (eh.e_ident[EI_CLASS] != ELFCLASS64)
    return "damaged: unknown ELF class " + std::to_string(eh.e_ident[EI_CLASS]) + " (not a 64-bit library)";
  if (eh.e_ident[EI_DATA] != host_data) {
    const char* here = host_data == ELFDATA2LSB ? "little-endian" : "big-endian";
    return eh.e_ident[EI_DATA] == ELFDATA2LSB || eh.e_ident[EI_DATA] == ELFDATA2MSB
               ? std::string("built for another byte order, this host is ") + here
               : "damaged: unknown ELF byte order " + std::to_string(eh.e_ident[EI_DATA]);
  }
  if (eh.e_ident[EI_VERSION] != EV_CURRENT || eh.e_version != EV_CURRENT)
    return "damaged: unknown ELF version " +
           std::to_string(eh.e_ident[EI_VERSION] != EV_CURRENT ? eh.e_ident[EI_VERSION] : eh.e_version);

  // What it is and what it runs on.
  switch (eh.e_type) {
    case ET_DYN: break;
    case ET_EXEC: return "an executable, not a shared library";
    case ET_REL: return "an object file (.o), not a shared library (build it with salsa_add_plugin)";
    case ET_CORE: return "a core dump, not a shared library";
    default: return "not a shared library (ELF type " + std::to_string(eh.e_type) + ")";
  }
  if (eh.e_machine != host_machine)
    return "built for " + machine_name(eh.e_machine) + ", this host is " + machine_name(host_machine);

  // The program headers, then everything dlopen maps or reads through them.
  if (eh.e_phentsize != sizeof(Elf64_Phdr))
    return "damaged: program header entries of " + bytes(eh.e_phentsize) + ", expected " + bytes(sizeof(Elf64_Phdr));
  if (eh.e_phnum == 0) return "no program headers (not a loadable library)";
  if (eh.e_phnum == PN_XNUM) return "damaged: 65535 or more program headers";
  const std::uint64_t ph_end = end_of(eh.e_phoff, eh.e_phnum, sizeof(Elf64_Phdr));
  if (ph_end == 0 || ph_end > size)
    return ph_end == 0 ? "damaged: the program headers lie past any file's end"
                       : truncated("the program header table", ph_end, size);

  auto header = [&](std::size_t i) { return read<Elf64_Phdr>(data + eh.e_phoff + i * sizeof(Elf64_Phdr)); };
  bool loads = false, dynamic = false;
  for (std::size_t i = 0; i < eh.e_phnum; ++i) {
    const auto ph = header(i);
    const std::string index = std::to_string(i);
    if (ph.p_type == PT_LOAD) {
      loads = true;
      if (ph.p_filesz > ph.p_memsz)
        return "damaged: loaded segment " + index + " has " + bytes(ph.p_filesz) + " in the file but only " +
               bytes(ph.p_memsz) + " in memory";
      if (end_of(ph.p_vaddr, 1, ph.p_memsz) == 0 && ph.p_memsz != 0)
        return "damaged: loaded segment " + index + " lies past the end of the address space";
      if (auto why = outside("loaded segment " + index, ph.p_offset, ph.p_filesz, size); !why.empty()) return why;
    } else if (ph.p_type == PT_DYNAMIC) {
      if (dynamic) return "damaged: two dynamic sections";
      dynamic = true;
      if (auto why = outside("the dynamic section (segment " + index + ")", ph.p_offset, ph.p_filesz, size); !why.empty())
        return why;
      // The loader walks the entries up to DT_NULL: it must come before the section ends.
      bool terminated = false;
      for (std::uint64_t at = 0; !terminated && at + sizeof(Elf64_Dyn) <= ph.p_filesz; at += sizeof(Elf64_Dyn))
        terminated = read<Elf64_Dyn>(data + ph.p_offset + at).d_tag == DT_NULL;
      if (!terminated) return "damaged: the dynamic section (segment " + index + ") has no end marker";
    }
  }
  if (!loads) return "no loadable segments (not a loadable library)";
  if (!dynamic) return "no dynamic section (not a shared library)";

  // Loaded segments ascend and do not overlap (at their alignment, as they are mapped): the ELF rule
  // glibc relies on without checking; an overlap maps one segment's zero fill over another's code.
  std::uint64_t previous_end = 0;
  for (std::size_t i = 0; i < eh.e_phnum; ++i) {
    const auto ph = header(i);
    if (ph.p_type != PT_LOAD) continue;
    const std::uint64_t align = ph.p_align > 1 ? ph.p_align : 1;
    if ((align & (align - 1)) != 0)
      return "damaged: loaded segment " + std::to_string(i) + " is aligned to " + std::to_string(align) +
             ", not a power of two";
    if ((ph.p_vaddr & ~(align - 1)) < previous_end)
      return "damaged: loaded segment " + std::to_string(i) + " overlaps the one before it";
    std::uint64_t rounded = 0;  // its end, rounded up to its alignment (vaddr + memsz cannot overflow: checked)
    if (__builtin_add_overflow(ph.p_vaddr + ph.p_memsz, align - 1, &rounded))
      return "damaged: loaded segment " + std::to_string(i) + " lies past the end of the address space";
    previous_end = rounded & ~(align - 1);
  }

  // What the dynamic loader reads or protects through the mapped image must lie inside a loaded
  // segment, or it touches unmapped memory: segments (the dynamic section, notes, the program headers,
  // the TLS image, the read-only-after-relocation range) and the tables the dynamic section points to.
  // mapped(): inside one loaded segment with `flags`, in its file-backed part and at that file offset
  // when `offset` is given, else anywhere in its memory.
  constexpr std::uint64_t in_memory = ~std::uint64_t(0);
  auto mapped = [&](std::uint64_t vaddr, std::uint64_t length, std::uint64_t offset, std::uint32_t flags = 0) {
    const std::uint64_t end = end_of(vaddr, 1, length);
    if (end == 0 && length != 0) return false;
    for (std::size_t j = 0; j < eh.e_phnum; ++j) {
      const auto load = header(j);
      if (load.p_type != PT_LOAD || vaddr < load.p_vaddr) continue;
      const bool file_backed = offset != in_memory;
      if (end > load.p_vaddr + (file_backed ? load.p_filesz : load.p_memsz)) continue;
      return (!file_backed || offset - load.p_offset == vaddr - load.p_vaddr) && (load.p_flags & flags) == flags;
    }
    return false;
  };
  Elf64_Phdr dyn{};
  for (std::size_t i = 0; i < eh.e_phnum; ++i) {
    const auto ph = header(i);
    const char* what = ph.p_type == PT_DYNAMIC                                     ? "the dynamic section"
                       : ph.p_type == PT_NOTE || ph.p_type == PT_GNU_PROPERTY       ? "a note"
                       : ph.p_type == PT_PHDR                                       ? "the program header table"
                       : ph.p_type == PT_TLS                                        ? "the thread-local data"
                       : ph.p_type == PT_GNU_RELRO                                  ? "the read-only-after-relocation range"
                                                                                    : nullptr;
    if (ph.p_type == PT_DYNAMIC) dyn = ph;
    const bool relro = ph.p_type == PT_GNU_RELRO;
    const std::uint64_t length = relro ? ph.p_memsz : ph.p_filesz;
    if (what && length != 0 && !mapped(ph.p_vaddr, length, relro ? in_memory : ph.p_offset))
      return "damaged: " + std::string(what) + " (segment " + std::to_string(i) + ") lies outside every loaded segment";
  }
  struct Table {
    std::int64_t address_tag, size_tag;
    const char* name;
    std::uint64_t address = 0, size = 0;
    bool present = false;
  };
  Table tables[] = {{DT_STRTAB, DT_STRSZ, "string table"},     {DT_SYMTAB, -1, "symbol table"},
                    {DT_HASH, -1, "hash table"},              {DT_GNU_HASH, -1, "GNU hash table"},
                    {DT_RELA, DT_RELASZ, "relocations"},      {DT_REL, DT_RELSZ, "relocations"},
                    {DT_JMPREL, DT_PLTRELSZ, "PLT relocations"}, {DT_INIT, -1, "init function"},
                    {DT_FINI, -1, "fini function"},           {DT_INIT_ARRAY, DT_INIT_ARRAYSZ, "init array"},
                    {DT_FINI_ARRAY, DT_FINI_ARRAYSZ, "fini array"}, {DT_PREINIT_ARRAY, DT_PREINIT_ARRAYSZ, "preinit array"},
                    {DT_PLTGOT, -1, "global offset table"},   {DT_VERSYM, -1, "symbol versions"},
                    {DT_VERDEF, -1, "version definitions"},   {DT_VERNEED, -1, "version needs"}};
  for (std::uint64_t at = 0; at + sizeof(Elf64_Dyn) <= dyn.p_filesz; at += sizeof(Elf64_Dyn)) {
    const auto d = read<Elf64_Dyn>(data + dyn.p_offset + at);
    if (d.d_tag == DT_NULL) break;
    for (Table& t : tables) {
      if (d.d_tag == t.address_tag) t.address = d.d_un.d_ptr, t.present = true;
      if (d.d_tag == t.size_tag) t.size = d.d_un.d_val;
    }
  }
  for (const Table& t : tables)
    if (t.present && !mapped(t.address, t.size == 0 ? 1 : t.size, in_memory))
      return std::string("damaged: the dynamic section's ") + t.name + " lies outside every loaded segment";

  // The section headers are not mapped, but linkers write them last: a file cut before their end
  // was not copied whole, even when every loaded segment made it.
  if (eh.e_shoff != 0) {
    if (eh.e_shentsize != sizeof(Elf64_Shdr))
      return "damaged: section header entries of " + bytes(eh.e_shentsize) + ", expected " + bytes(sizeof(Elf64_Shdr));
    const std::uint64_t sh_end = end_of(eh.e_shoff, eh.e_shnum == 0 ? 1 : eh.e_shnum, sizeof(Elf64_Shdr));
    if (sh_end == 0) return "damaged: the section headers lie past any file's end";
    if (sh_end > size) return truncated("the section header table", sh_end, size);
    // When present, the sections the segments carry must agree with them: in the file-backed part
    // of a loaded segment, at the same offset, code in an executable one, data in a writable one.
    for (std::size_t i = 0; i < eh.e_shnum; ++i) {
      const auto sh = read<Elf64_Shdr>(data + eh.e_shoff + i * sizeof(Elf64_Shdr));
      if (!(sh.sh_flags & SHF_ALLOC) || sh.sh_size == 0 || (sh.sh_flags & SHF_TLS)) continue;
      const std::uint32_t needs = ((sh.sh_flags & SHF_EXECINSTR) ? PF_X : 0) | ((sh.sh_flags & SHF_WRITE) ? PF_W : 0);
      bool fits = false;
      if (sh.sh_type != SHT_NOBITS) fits = mapped(sh.sh_addr, sh.sh_size, sh.sh_offset, needs);
      else  // zero-filled data (.bss): in the memory-only part, past what the file supplies
        for (std::size_t j = 0; j < eh.e_phnum && !fits; ++j) {
          const auto load = header(j);
          const std::uint64_t end = end_of(sh.sh_addr, 1, sh.sh_size);
          fits = load.p_type == PT_LOAD && end != 0 && sh.sh_addr >= load.p_vaddr + load.p_filesz &&
                 end <= load.p_vaddr + load.p_memsz && (load.p_flags & needs) == needs;
        }
      if (!fits) return "damaged: section " + std::to_string(i) + " does not match the loaded segments";
    }
  }
  return {};
}

}  // namespace salsa
