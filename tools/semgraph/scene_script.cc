// Scene scripts from C++. Contract: semgraph/script/scene_script.h.
#include "semgraph/script/scene_script.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <new>
#include <utility>

#include "semgraph/script_reader.h"
#include "semgraph/script_runner.h"

namespace semgraph::script {

namespace {

// The stage a run was in when memory ran out, for the message.
struct Progress {
  bool reading = true;
  std::size_t op = 0;
  int line = 0;
};

std::string OutOfMemory(std::string_view name, const Progress& p) {
  if (p.reading) return std::string(name) + ": out of memory while reading the script";
  return std::string(name) + ":" + std::to_string(p.line) + ": out of memory while applying op " +
         std::to_string(p.op) + " (the ops before it were applied)";
}

// Applies every op of `script` to `graph`; `progress` says how far it got.
template <coord::Backend B>
void Apply(const Script& script, core::SceneGraph<B>& graph, const RunOptions& options,
           SceneRun* run, Progress* progress) {
  progress->reading = false;
  bool all_ok = true;
  for (std::size_t i = 0; i < script.ops.size(); ++i) {
    progress->op = i;
    progress->line = script.ops[i].location.line;
    OpOutcome outcome = ApplyOp(graph, script.ops[i], i, options.base_dir);
    all_ok = all_ok && outcome.ok;
    OpResult result{i,
                    outcome.ok,
                    std::move(outcome.error),
                    std::move(outcome.json),
                    OpLabel(script.ops[i]),
                    script.ops[i].location.line};
    if (options.on_op) {
      if (!options.on_op(result)) break;
    } else {
      run->ops.push_back(std::move(result));
    }
  }
  run->status = all_ok ? kExitOk : kExitOpFailed;
}

// Reads the script; on success runs `then(script)`. Every std::bad_alloc ends here.
template <typename Then>
SceneRun ReadThen(std::string_view text, const RunOptions& options, Then&& then) {
  SceneRun run;
  Progress progress;
  try {
    const auto script = ReadScript(text);
    if (!script) {
      run.status = kExitMalformed;
      run.error = FormatScriptError(options.display_name, script.error());
      run.error_line = script.error().location.line;
      run.error_column = script.error().location.column;
      run.error_message = script.error().message;
      return run;
    }
    then(*script, &run, &progress);
  } catch (const std::bad_alloc&) {
    run.status = kExitMalformed;
    run.out_of_memory = true;
    run.error = OutOfMemory(options.display_name, progress);
  }
  return run;
}

SceneRun Unreadable(const std::string& name, const std::string& reason) {
  SceneRun run;
  run.status = kExitMalformed;
  run.error = name + ": cannot read: " + reason;
  return run;
}

void DefaultName(const std::string& path, RunOptions* options) {
  if (options->display_name == RunOptions{}.display_name) {
    options->display_name = path == "-" ? "<stdin>" : path;
  }
  if (options->base_dir.empty() && path != "-") {  // the script's folder
    const std::size_t slash = path.rfind('/');
    options->base_dir =
        slash == std::string::npos ? std::string() : path.substr(0, slash == 0 ? 1 : slash);
  }
}

}  // namespace

bool ReadScriptFile(const std::string& path, std::string* text, std::string* error) {
  std::FILE* file = path == "-" ? stdin : std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    *error = std::strerror(errno);
    return false;
  }
  char buffer[1 << 16];
  bool ok = true;
  text->clear();
  while (text->size() <= kMaxScriptBytes) {
    const std::size_t n = std::fread(buffer, 1, sizeof(buffer), file);
    text->append(buffer, n);
    if (n < sizeof(buffer)) {
      if (std::ferror(file)) {
        *error = std::strerror(errno);
        ok = false;
      }
      break;
    }
  }
  if (file != stdin) std::fclose(file);
  return ok;
}

BuiltScene BuildScene(std::string_view text, const RunOptions& options) {
  BuiltScene built;
  built.run = ReadThen(text, options, [&](const Script& script, SceneRun* run, Progress* progress) {
    const auto go = [&](auto& graph) {
      Apply(script, graph, options, run, progress);
      if (options.dot) run->dot = WriteDot(graph);
      if (options.scene) run->scene = WriteScene(graph);
    };
    const core::TimeOptions time = TimeOptionsOf(script.time);  // Create cannot refuse them
    // Made in place, so that the graph the ops went into is the one handed over.
    if (script.representation == Representation::kHomogeneous) {
      using G = core::SceneGraph<coord::HomogeneousBackend>;
      go(built.graph.emplace<G>(std::move(*G::Create(time))));
    } else {
      using G = core::SceneGraph<coord::QuaternionBackend>;
      go(built.graph.emplace<G>(std::move(*G::Create(time))));
    }
  });
  return built;
}

SceneRun RunScene(std::string_view text, const RunOptions& options) {
  return BuildScene(text, options).run;
}

SceneRun RunSceneFile(const std::string& path, RunOptions options) {
  DefaultName(path, &options);
  std::string text, reason;
  try {
    if (!ReadScriptFile(path, &text, &reason)) return Unreadable(options.display_name, reason);
  } catch (const std::bad_alloc&) {
    SceneRun run = Unreadable(options.display_name, "out of memory");
    run.out_of_memory = true;
    return run;
  }
  return RunScene(text, options);
}

template <coord::Backend B>
SceneRun LoadScene(std::string_view text, core::SceneGraph<B>& graph, const RunOptions& options) {
  return ReadThen(text, options, [&](const Script& script, SceneRun* run, Progress* progress) {
    Apply(script, graph, options, run, progress);
  });
}

template <coord::Backend B>
SceneRun LoadSceneFile(const std::string& path, core::SceneGraph<B>& graph, RunOptions options) {
  DefaultName(path, &options);
  std::string text, reason;
  try {
    if (!ReadScriptFile(path, &text, &reason)) return Unreadable(options.display_name, reason);
  } catch (const std::bad_alloc&) {
    SceneRun run = Unreadable(options.display_name, "out of memory");
    run.out_of_memory = true;
    return run;
  }
  return LoadScene(text, graph, options);
}

template SceneRun LoadScene(std::string_view, core::SceneGraph<coord::QuaternionBackend>&,
                            const RunOptions&);
template SceneRun LoadScene(std::string_view, core::SceneGraph<coord::HomogeneousBackend>&,
                            const RunOptions&);
template SceneRun LoadSceneFile(const std::string&, core::SceneGraph<coord::QuaternionBackend>&,
                                RunOptions);
template SceneRun LoadSceneFile(const std::string&, core::SceneGraph<coord::HomogeneousBackend>&,
                                RunOptions);

}  // namespace semgraph::script
