// Element quality: implemented with the meshing work.
