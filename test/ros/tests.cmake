# rostests of the nodelets
