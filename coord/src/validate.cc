namespace semgraph::coord {}
