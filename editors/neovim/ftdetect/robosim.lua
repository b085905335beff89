-- Sourced by `:filetype on` from every ftdetect/ folder on 'runtimepath'.
-- .rct → robochart, .assertions → robochart-assertions,
-- .rsa → robosim-assertions, .rst → robosim only when it looks like RoboSim.
require('robosim.filetype').setup()
