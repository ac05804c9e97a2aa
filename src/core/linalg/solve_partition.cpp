// splitSolves: the fixed split of the triangular solves over the elimination tree
// (supernodal_solves.h, SolveTasks).
#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

#include "cloth_sim/core/linalg/supernodal_solves.h"

namespace cloth_sim {
namespace {

/// The supernodes' elimination tree, with each subtree's work (factor entries).
struct Tree {
  std::vector<int> parent;                 ///< -1 for a root
  std::vector<std::vector<int>> children;  ///< increasing
  std::vector<long> work;                  ///< entries of the subtree
  std::vector<int> roots;
};

Tree treeOf(const SupernodalFactor& f) {
  const int count = f.supernodeCount();
  std::vector<int> super_of(f.size);
  for (int s = 0; s < count; ++s) {
    for (int c = f.first_column[s]; c < f.first_column[s + 1]; ++c) super_of[c] = s;
  }
  Tree t;
  t.parent.assign(count, -1);
  t.children.resize(count);
  t.work.assign(count, 0);
  for (int s = 0; s < count; ++s) {
    const long w = f.first_column[s + 1] - f.first_column[s];
    t.work[s] += w * (w + 1) / 2 + w * (f.row_start[s + 1] - f.row_start[s]);
    if (f.row_start[s + 1] > f.row_start[s]) {
      // The first row below the block is the parent of the supernode's last column.
      const int p = super_of[f.rows[f.row_start[s]]];
      if (p <= s) throw std::logic_error("splitSolves: the factor's columns are not in topological order");
      t.parent[s] = p;
      t.children[p].push_back(s);
      t.work[p] += t.work[s];  // s < p: s's subtree is complete here
    } else {
      t.roots.push_back(s);
    }
  }
  return t;
}

/// Recursive bisection of the tree into tasks (see splitSolves).
class Splitter {
 public:
  Splitter(const Tree& tree, int max_depth, long min_task)
      : tree_(tree), max_depth_(max_depth), min_task_(min_task) {}

  struct Draft {
    std::vector<int> supernodes;
    int depth = 0;
    bool leaf = false;
    int parent = -1;  ///< the separator draft above it
  };

  void split(std::vector<int> forest, int depth, int parent) {
    Draft own{{}, depth, false, parent};
    while (true) {
      const long total = workOf(forest);
      if (depth >= max_depth_ || total < 2 * min_task_ || forest.empty()) {
        for (int r : forest) collect(r, own.supernodes);
        own.leaf = true;
        break;
      }
      std::sort(forest.begin(), forest.end(),
                [&](int a, int b) { return std::make_pair(-tree_.work[a], a) < std::make_pair(-tree_.work[b], b); });
      std::vector<int> bins[2];
      long load[2] = {0, 0};
      for (int r : forest) {
        const int to = load[1] < load[0] ? 1 : 0;
        bins[to].push_back(r);
        load[to] += tree_.work[r];
      }
      if (forest.size() >= 2 && std::max(load[0], load[1]) <= 0.6 * total) {
        drafts_.push_back(own);  // the separator above the two halves
        const int self = static_cast<int>(drafts_.size()) - 1;
        split(bins[0], depth + 1, self);
        split(bins[1], depth + 1, self);
        return;
      }
      // One tree, or one that outweighs the rest: its root goes to this task, its children
      // replace it.
      const int top = forest.front();
      own.supernodes.push_back(top);
      forest.erase(forest.begin());
      forest.insert(forest.end(), tree_.children[top].begin(), tree_.children[top].end());
    }
    drafts_.push_back(own);
  }

  std::vector<Draft>& drafts() { return drafts_; }

 private:
  long workOf(const std::vector<int>& forest) const {
    long total = 0;
    for (int r : forest) total += tree_.work[r];
    return total;
  }
  void collect(int root, std::vector<int>& out) const {
    std::vector<int> stack{root};
    while (!stack.empty()) {
      const int s = stack.back();
      stack.pop_back();
      out.push_back(s);
      stack.insert(stack.end(), tree_.children[s].begin(), tree_.children[s].end());
    }
  }

  const Tree& tree_;
  int max_depth_;
  long min_task_;
  std::vector<Draft> drafts_;
};

}  // namespace

namespace {

void splitInto(SupernodalFactor& f, int max_depth, long min_task) {
  f.scratch.clear();
  const int count = f.supernodeCount();
  for (int s = 0; s < count; ++s) f.own_count[s] = f.row_start[s + 1] - f.row_start[s];
  if (count == 0) return;
  const Tree tree = treeOf(f);
  Splitter splitter(tree, max_depth, min_task);
  splitter.split(tree.roots, 0, -1);
  // Empty separators (a forest split at once) go; their children hang from their parent.
  std::vector<Splitter::Draft>& all = splitter.drafts();
  std::vector<int> kept(all.size(), -1);
  std::vector<char> empty(all.size());
  for (std::size_t d = 0; d < all.size(); ++d) empty[d] = all[d].supernodes.empty();
  std::vector<Splitter::Draft> drafts;
  for (std::size_t d = 0; d < all.size(); ++d) {
    int parent = all[d].parent;
    while (parent >= 0 && empty[parent]) parent = all[parent].parent;
    all[d].parent = parent < 0 ? -1 : kept[parent];  // parents come first (pre-order)
    if (all[d].supernodes.empty()) continue;
    kept[d] = static_cast<int>(drafts.size());
    drafts.push_back(std::move(all[d]));
  }
  if (drafts.size() <= 1) return;  // nothing runs beside anything: the plain serial solves

  // Phases: every leaf first; then the separators, deepest first.
  int deepest = 0;
  for (const auto& d : drafts) deepest = std::max(deepest, d.leaf ? 0 : d.depth);
  const auto phase = [&](const Splitter::Draft& d) { return d.leaf ? 0 : 1 + deepest - d.depth; };
  std::vector<int> order(drafts.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return phase(drafts[a]) < phase(drafts[b]); });
  std::vector<int> task_index(drafts.size());
  for (std::size_t t = 0; t < order.size(); ++t) task_index[order[t]] = static_cast<int>(t);
  {
    std::vector<Splitter::Draft> sorted;
    for (int d : order) {
      sorted.push_back(std::move(drafts[d]));
      if (sorted.back().parent >= 0) sorted.back().parent = task_index[sorted.back().parent];
    }
    drafts.swap(sorted);
  }
  SolveTasks& tasks = f.tasks;
  std::vector<int> task_of_column(f.size, -1);
  for (std::size_t t = 0; t < drafts.size(); ++t) {
    SolveTasks::Task task;
    task.supernodes = drafts[t].supernodes;
    task.depth = drafts[t].depth;
    task.leaf = drafts[t].leaf;
    task.parent = drafts[t].parent;
    std::sort(task.supernodes.begin(), task.supernodes.end());
    for (int s : task.supernodes) {
      for (int c = f.first_column[s]; c < f.first_column[s + 1]; ++c) task_of_column[c] = static_cast<int>(t);
    }
    tasks.tasks.push_back(std::move(task));
    const int p = phase(drafts[t]);
    while (static_cast<int>(tasks.phase_begin.size()) <= p) tasks.phase_begin.push_back(static_cast<int>(t));
  }
  tasks.phase_begin.push_back(static_cast<int>(drafts.size()));

  // Each task's outside rows get its slots; the rows below each supernode are renumbered.
  std::vector<int> slot_of_row(f.size, -1);
  for (std::size_t t = 0; t < tasks.tasks.size(); ++t) {
    SolveTasks::Task& task = tasks.tasks[t];
    task.slot_begin = tasks.slots;
    for (int s : task.supernodes) {
      int own = 0;
      for (int i = f.row_start[s]; i < f.row_start[s + 1]; ++i) {
        const int r = f.rows[i];
        if (task_of_column[r] == static_cast<int>(t)) {
          if (own != i - f.row_start[s]) throw std::logic_error("splitSolves: a task's rows interleave");
          ++own;
          continue;
        }
        if (phase(drafts[task_of_column[r]]) <= phase(drafts[t])) {
          throw std::logic_error("splitSolves: row " + std::to_string(r) + " is not an ancestor's");
        }
        if (slot_of_row[r] < 0) {
          slot_of_row[r] = tasks.slots++;
          task.slot_row.push_back(r);
        }
      }
      f.own_count[s] = own;
    }
    // Slots in row order (so each supernode's slots increase, as its rows did).
    std::sort(task.slot_row.begin(), task.slot_row.end());
    for (std::size_t k = 0; k < task.slot_row.size(); ++k) {
      slot_of_row[task.slot_row[k]] = task.slot_begin + static_cast<int>(k);
    }
    for (int s : task.supernodes) {
      for (int i = f.row_start[s] + f.own_count[s]; i < f.row_start[s + 1]; ++i) f.rows[i] = slot_of_row[f.rows[i]];
    }
    for (int r : task.slot_row) slot_of_row[r] = -1;
  }
  // Gathers: each slot's row belongs to a later task, which adds it, by row then by slot.
  std::vector<std::vector<std::pair<int, int>>> gathers(tasks.tasks.size());
  for (const SolveTasks::Task& task : tasks.tasks) {
    for (std::size_t k = 0; k < task.slot_row.size(); ++k) {
      const int r = task.slot_row[k];
      gathers[task_of_column[r]].emplace_back(r, task.slot_begin + static_cast<int>(k));
    }
  }
  for (std::size_t t = 0; t < tasks.tasks.size(); ++t) {
    std::sort(gathers[t].begin(), gathers[t].end());
    for (const auto& [row, slot] : gathers[t]) {
      tasks.tasks[t].gather_row.push_back(row);
      tasks.tasks[t].gather_slot.push_back(slot);
    }
  }
  f.scratch.assign(static_cast<std::size_t>(kNodeStride) * tasks.slots, 0.0);
}

}  // namespace

const SolveTasks::Schedule& SolveTasks::schedule(int threads) const {
  threads = std::max(threads, 1);
  if (schedule_.threads == threads) return schedule_;
  Schedule& out = schedule_;
  out = Schedule{};
  out.threads = threads;
  int level = 0;
  while ((1 << level) < threads) ++level;
  // Each task's group: its highest ancestor-or-self at depth >= level (a leaf above that level
  // is a group of its own); -1 for the separators above the level.
  const int count = static_cast<int>(tasks.size());
  std::vector<int> group_of(count, -1), group_index(count, -1);
  for (int t = count - 1; t >= 0; --t) {  // parents come after their children here
    const Task& task = tasks[t];
    if (task.depth < level && !task.leaf) continue;
    int root = t;
    while (tasks[root].parent >= 0 && tasks[tasks[root].parent].depth >= level) root = tasks[root].parent;
    group_of[t] = root;
  }
  for (int t = 0; t < count; ++t) {  // in phase order: each group's tasks come out in order
    if (group_of[t] < 0) continue;
    int& g = group_index[group_of[t]];
    if (g < 0) {
      g = static_cast<int>(out.groups.size());
      out.groups.emplace_back();
    }
    out.groups[g].push_back(t);
  }
  for (int p = 0; p < phases(); ++p) {
    std::vector<int> phase;
    for (int t = phase_begin[p]; t < phase_begin[p + 1]; ++t) {
      if (group_of[t] < 0) phase.push_back(t);
    }
    if (!phase.empty()) out.top.push_back(std::move(phase));
  }
  return out;
}

void splitSolves(SupernodalFactor& f, int max_depth, long min_task) {
  const std::vector<int> rows = f.rows;
  f.tasks = SolveTasks{};
  try {
    splitInto(f, max_depth, min_task);
  } catch (const std::logic_error&) {
    // A tree the split does not understand (not postordered): the serial solves, unsplit.
    f.rows = rows;
    f.tasks = SolveTasks{};
    f.scratch.clear();
    for (int s = 0; s < f.supernodeCount(); ++s) f.own_count[s] = f.row_start[s + 1] - f.row_start[s];
  }
}

}  // namespace cloth_sim
