"""What the add-on draws: the Geometry Nodes groups, modifiers, materials and child objects
that show road surfaces (surface), nonterminal frames (frames), pattern colours
(patterns), a learned grammar's levels (rules) and the 3-D city (city); road_objects makes
road graph objects with what draws them; nodes holds the helpers they share. Display draws
what data holds: it imports data, data never imports it."""
