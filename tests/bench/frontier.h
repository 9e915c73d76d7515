// bullet_compare --frontier: the accuracy-cost frontier of voxfall and Bullet per scene.
#pragma once

namespace vf::bench {

// `bullet_compare --frontier [--rounds N] [--scenes a,b,...] [--cap S] CSV_DIR FIGURE_BASE`:
// runs the grid, writes CSV_DIR/bullet_frontier.csv and bullet_frontier_verdict.csv and
// FIGURE_BASE.png/.svg, and prints the verdict as markdown. argv[0] is "--frontier". Returns
// the exit status; throws on bad arguments or an unreadable scene.
int frontierMain(int argc, char** argv);

}  // namespace vf::bench
