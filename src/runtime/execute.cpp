#include "execute.h"

#include <map>
#include <memory>
#include <mutex>
#include <set>

#include "keys.h"
#include "olt/core/error.h"
#include "olt/core/hash.h"
#include "olt/core/process_memory.h"
#include "publish_list.h"
#include "unit_engine.h"

namespace olt {

std::map<std::string, StageInput> stage_inputs(const StageDecl& stage, const std::map<std::string, Artifact>& done,
                                               SharedReads* shared) {
  std::map<std::string, StageInput> inputs;
  for (const auto& [kind, id] : stage.inputs) inputs.emplace(kind, StageInput{id, done.at(id), shared});
  return inputs;
}

std::map<std::string, std::string> input_digests(const std::map<std::string, StageInput>& inputs) {
  std::map<std::string, std::string> digests;
  for (const auto& [kind, input] : inputs) digests[kind] = input.artifact.digest;
  return digests;
}

std::optional<Artifact> previous_artifact(const Job& job, const StageDecl& stage, const Store& store) {
  const auto record = store.record(job_id(job), stage.id);
  return record ? store.find(key_of(*record)) : std::nullopt;
}

namespace {

// The name a process that keeps memory (`olt watch`) keeps a piece's bytes under, with their digest.
std::string kept_piece_name(const std::string& key) { return "piece bytes " + key; }

// The bytes of the piece `found` (its "bytes" listed as `sha256`) this process kept, while the file is
// there with its size; null where it kept none. A file damaged since to other bytes of its size is
// found by a process that keeps nothing, as the store's entries are (Store::find).
std::shared_ptr<const std::string> kept_piece(const Store& store, const Artifact& found, const std::string& sha256) {
  if (!keeping_memory()) return nullptr;
  auto kept = remembered_from<std::string>(kept_piece_name(found.key), sha256);
  if (!kept) return nullptr;
  const FileStat st = store.files().stat(found.path("bytes"));
  return st.is_file() && st.size == kept->size() ? kept : nullptr;
}

void keep_piece(const std::string& key, const std::string& sha256, const std::string& bytes) {
  if (keeping_memory())
    remember_from<std::string>(kept_piece_name(key), sha256, std::make_shared<const std::string>(bytes), bytes.size());
}

void forget_piece_bytes(const std::string& key) { forget_from<std::string>(kept_piece_name(key)); }

// The pieces a stage's run used, each referred to from its artifact (`out`) once: `olt cache gc`
// keeps what the artifact refers to, so the next edit finds the pieces still there.
class PiecesUsed {
 public:
  explicit PiecesUsed(ArtifactWriter& out) : out_(out) {}
  void refer(const std::string& key, const Artifact& piece) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (keys_.insert(key).second) out_.refer("pieces/" + key, piece, "bytes");
  }
  std::vector<std::string> used() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return {keys_.begin(), keys_.end()};
  }

 private:
  ArtifactWriter& out_;
  mutable std::mutex mutex_;
  std::set<std::string> keys_;
};

// StageContext::memo on the cache: a "piece-<key>" entry holding the bytes, keyed by the record with
// the stage's kind and its version (a change to how the kind draws bumps it, as for its artifacts).
// Bytes that are not those recorded (a damaged entry) are made again and replace it. Each piece used
// is told to `pieces`, where given (a stage's run). A process that keeps memory keeps the bytes it
// read or made: the report's pictures are not read and hashed again every cycle of `olt watch`.
Memo cache_memo(const Store& store, const StageKind& kind, std::shared_ptr<PiecesUsed> pieces) {
  return [&store, &kind, pieces](const nlohmann::json& record, const std::function<std::string()>& make) {
    const nlohmann::json keyed = {{"kind", kind.spec.name}, {"version", kind.version}, {"piece", record}};
    const std::string key = "piece-" + sha256_hex(keyed.dump());
    const auto refer = [&](const Artifact& piece) {
      if (pieces) pieces->refer(key, piece);
    };
    if (const auto found = store.find(key); found && found->file("bytes")) {
      const std::string listed = found->file("bytes")->sha256.hex();
      if (const auto kept = kept_piece(store, *found, listed)) {
        refer(*found);
        return *kept;
      }
      try {
        std::string bytes = store.files().read(found->path("bytes"));
        if (sha256_hex(bytes) == listed) {
          refer(*found);
          keep_piece(key, listed, bytes);
          return bytes;
        }
        store.drop(key);
      } catch (const std::exception&) {  // removed meanwhile (gc): made again
      }
    }
    std::string bytes = make();
    const fs::path dir = store.begin(key);
    try {
      store.files().write(dir / "bytes", bytes);
      refer(store.commit(key, dir));
    } catch (...) {
      store.discard(dir);
      throw;
    }
    keep_piece(key, sha256_hex(bytes), bytes);
    return bytes;
  };
}

}  // namespace

StageContext stage_context(const Job& job, const StageDecl& stage, const std::map<std::string, StageInput>& inputs,
                           FileDigests& digests, const Store* store, const StageKind* kind) {
  StageContext context{job.file, job.output, stage, inputs,
                       [&digests](const fs::path& file) { return digests.digest(file); }};
  if (store && kind) context.memo = cache_memo(*store, *kind, nullptr);
  return context;
}

RunOutcome run_into(const StageContext& context, const StageKind& kind, const Store& store, ArtifactFolder& out,
                    int merge_shards, const std::atomic<bool>* stop) {
  RunOutcome outcome;
  as_stage(context.stage, [&] {
    if (kind.units) {
      const auto work = kind.units(context);
      if (merge_shards > 0) check_units_cached(*work, kind.unit_words, store, context.stage.id, merge_shards);
      outcome.report = run_units(*work, kind.unit_words, store, out, stop, context.kept_name("unit entries"));
      outcome.summary = work->assemble(context, out);
    } else {
      outcome.summary = kind.run(context, out);
    }
    out.write_pieces("publish.json", [&](const PieceSink& sink) { out.publish_list(sink); });
    out.write("summary.json", outcome.summary.dump(1));
  });
  return outcome;
}

namespace {

// The files the stage's last run in this process wrote (`olt watch`'s last cycle), where their bytes
// are, but those of an entry the store no longer holds (removed by hand, or as damaged) and those of
// `key`, the entry about to be made (made again because it was damaged). An entry held is a stat, its
// files not checked: a file damaged inside it is referred to again, as the daemon refers to the
// frames' entries it found, until a run finds it of another size or `olt cache verify` hashes it.
ArtifactFiles written_before(const std::string& name, const std::string& key, const Store& store) {
  const auto before = remembered<ArtifactFiles>(name);
  if (!before) return {};
  std::map<std::string_view, bool> held;  // by entry
  for (const ListedFile f : *before) held.emplace(f.in, false);
  for (auto& [in, is_held] : held) is_held = in != key && store.holds(std::string(in));
  ArtifactFiles files;
  for (const ListedFile f : *before)
    if (held.at(f.in)) files.add(f.path, f.sha256, f.size, f.in, f.as);
  return files;
}

}  // namespace

Artifact execute(const StageContext& context, const StageKind& kind, const std::string& key, const Store& store,
                 int merge_shards, nlohmann::json* summary, const std::atomic<bool>* stop) {
  const fs::path dir = store.begin(key);
  try {
    ArtifactFolder out(dir, store.files());
    // A process that keeps memory writes again only the files whose bytes changed since its last run
    // of the stage; the others are referred to where they are.
    const std::string written_name = context.kept_name("files written");
    if (keeping_memory()) out.carry_from(written_before(written_name, key, store));
    StageContext run = context;
    const auto pieces = std::make_shared<PiecesUsed>(out);  // referred to from its artifact
    run.memo = cache_memo(store, kind, pieces);
    const RunOutcome outcome = run_into(run, kind, store, out, merge_shards, stop);
    *summary = outcome.summary;
    summary->update(outcome.report);
    Artifact made = store.commit(key, dir, out.take_described());
    if (keeping_memory()) {
      auto written = std::make_shared<const ArtifactFiles>(out.carried_forward(made));
      remember<ArtifactFiles>(written_name, written, written->bytes());
      // An edit makes the labeling stage's entry again each cycle (its list of 2,240 files on the
      // robot), and the report's pieces of the box it moved: those of the cycle before let go.
      store.forget_unused(context.kept_name("entry made"), {made.key});
      for (const std::string& piece : store.forget_unused(context.kept_name("pieces used"), pieces->used()))
        forget_piece_bytes(piece);
    }
    return made;
  } catch (...) {
    store.discard(dir);
    throw;
  }
}

}  // namespace olt
